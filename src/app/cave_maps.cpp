#include "app/cave_maps.h"

#include "formats/passages.h"

namespace cavesim::app {

bool isSection(const Dims& dims) {
    return dims.ny == 1 && dims.nx > 1 && dims.nz > 1;
}

render::CaveMapInput caveMapInput(const Cave& cave, const morpho::Skeleton& skeleton, const std::string& title) {
    render::CaveMapInput in;
    in.title = title;
    const Dims& d = cave.dims();
    const double h = cave.voxelSize;
    in.blockMax = {d.nx * h, d.ny * h, d.nz * h};
    const std::vector<morpho::Branch> passages = formats::findPassages(skeleton);
    const std::vector<std::string> names = formats::stationNames(skeleton, passages);
    for (std::size_t n = 0; n < skeleton.nodes.size(); ++n)
        in.stations.push_back({skeleton.nodes[n].position, skeleton.nodes[n].radius, names[n]});
    for (const morpho::Branch& b : passages)
        if (b.nodes.size() >= 2) in.passages.push_back(b.nodes);
    auto centre = [&](const std::vector<std::size_t>& voxels) {
        Vec3d c{0, 0, 0};
        for (std::size_t v : voxels) {
            const Index3 p = d.coord(v);
            c = {c[0] + (p.i + 0.5) * h, c[1] + (p.j + 0.5) * h, c[2] + (p.k + 0.5) * h};
        }
        const double n = double(std::max<std::size_t>(voxels.size(), 1));
        return Vec3d{c[0] / n, c[1] / n, c[2] / n};
    };
    for (const auto& s : cave.sourceVoxels)
        if (!s.empty()) in.sources.push_back(centre(s));
    for (const auto& s : cave.sinkVoxels)
        if (!s.empty()) in.sinks.push_back(centre(s));
    return in;
}

std::vector<std::string> writeCaveMaps(const Cave& cave, const morpho::Skeleton& skeleton, const std::string& title,
                                       const std::string& imagesDir, int width) {
    return render::writeCaveMaps(caveMapInput(cave, skeleton, title), isSection(cave.dims()), imagesDir, width);
}

}  // namespace cavesim::app
