// A hand-made cave with known answers, shared by test_formats and formats_sample.
//
// Grid 12 × 8 × 6 voxels of 0.5 m. Cave (flagged channel): a main passage i 1–10, j 3–4, k 2–3
// (x 0.5–5.5 m, y 1.5–2.5 m, z 1–2 m) and a side passage i 5–6, j 5–7, k 2–3 (x 2.5–3.5 m,
// y 2.5–4 m: it reaches the block's north face). 52 cave voxels.
// Skeleton: main axis y = 2, z = 1.5 with nodes at x = 1, 2, 3, 4, 5; side nodes (3, 3, 1.5) and
// (3, 3.8, 1.5); junction node 2 at (3, 2, 1.5). Radii 0.5 m.
#pragma once

#include <cmath>

#include "core/surface_mesh.h"
#include "morpho/skeleton_graph.h"
#include "sim/domain.h"
#include "sim/stage2.h"

namespace cavesim::formats::test {

struct Sample {
    Domain domain;
    morpho::Skeleton skeleton;
    SurfaceMesh box;  ///< the box [0, 1] × [0, 2] × [0, 3] m, outward
    Stage2Result stage2;
};

inline Sample makeSample() {
    Sample s;
    s.domain = emptyDomain({12, 8, 6}, 0.5, 0.1f);
    Domain& d = s.domain;
    auto mark = [&d](int i0, int i1, int j0, int j1, int k0, int k1) {
        for (int k = k0; k <= k1; ++k)
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    d.flags.at(i, j, k) = kChannel;
                    d.porosity.at(i, j, k) = 1.0f;
                    d.flow.at(i, j, k) = float(i);  // flow grows east: known node values
                    d.pressure.at(i, j, k) = 0.25f;
                    d.water.at(i, j, k) = 0.5f;
                    d.zone.at(i, j, k) = 1;
                }
    };
    mark(1, 10, 3, 4, 2, 3);
    mark(5, 6, 5, 7, 2, 3);
    d.zone.at(0, 0, 0) = -1;

    const double h = d.voxelSize;
    auto node = [&](double x, double y, double z) {
        morpho::SkeletonNode n;
        n.position = {x, y, z};
        n.radius = 0.5;
        n.voxel = d.dims.index(int(std::floor(x / h)), int(std::floor(y / h)), int(std::floor(z / h)));
        s.skeleton.nodes.push_back(n);
    };
    for (double x : {1.0, 2.0, 3.0, 4.0, 5.0}) node(x, 2.0, 1.5);
    node(3.0, 3.0, 1.5);
    node(3.0, 3.8, 1.5);
    s.skeleton.edges = {{0, 1}, {1, 2}, {2, 3}, {2, 5}, {3, 4}, {5, 6}};

    s.box.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 2, 0}, {0, 2, 0}, {0, 0, 3}, {1, 0, 3}, {1, 2, 3}, {0, 2, 3}};
    for (const auto& v : s.box.vertices) {
        std::array<float, 3> n{};
        for (int c = 0; c < 3; ++c) n[c] = v[c] > 0 ? 1.f : -1.f;
        const float len = std::sqrt(3.f);
        s.box.normals.push_back({n[0] / len, n[1] / len, n[2] / len});
    }
    s.box.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                       {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};

    for (int it = 1; it <= 3; ++it) {
        Stage2Record r;
        r.iteration = it;
        r.injected = 1.5 * it;
        r.drained = 0.25;
        r.stored = 10 + it;
        r.flow = 0.1 * it;
        r.eroded = 0.125;
        r.channelVoxels = 40 + it;
        r.pressureUpdates = 7;
        r.sourcesConnected = it / 2;
        r.balanceError = 1e-12;
        s.stage2.history.push_back(r);
    }
    s.stage2.iterations = 3;
    return s;
}

}  // namespace cavesim::formats::test
