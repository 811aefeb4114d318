#include "mesh/vdb_io.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <iterator>

#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetRebuild.h>

#include <sstream>
#include <string>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/fnv.h"
#include "mesh/cave_level_set.h"
#include "sim/cave.h"

namespace cavesim::mesh {
namespace {

openvdb::math::Transform::Ptr transformFor(double voxelSize, const std::array<double, 3>& origin = {0, 0, 0}) {
    auto xf = openvdb::math::Transform::createLinearTransform(voxelSize);
    // Index (i,j,k) is the voxel whose centre is at origin + (i+0.5)·h.
    xf->postTranslate(
        openvdb::Vec3d(origin[0] + 0.5 * voxelSize, origin[1] + 0.5 * voxelSize, origin[2] + 0.5 * voxelSize));
    return xf;
}

template <typename GridT, typename T>
typename GridT::Ptr denseToGrid(const Grid3<T>& g, double voxelSize, const std::array<double, 3>& origin = {0, 0, 0}) {
    auto grid = GridT::create(T(0));
    auto acc = grid->getAccessor();
    const Dims& d = g.dims;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const T v = g.at(i, j, k);
                if (v != T(0)) acc.setValue(openvdb::Coord(i, j, k), v);
            }
    grid->setTransform(transformFor(voxelSize, origin));
    return grid;
}

template <typename GridT, typename T>
Grid3<T> gridToDense(const std::string& path, const std::string& name, const Dims& dims) {
    openvdb::initialize();
    openvdb::io::File file(path);
    try {
        file.open();
    } catch (const openvdb::Exception& e) {
        throw RuntimeError("cannot open " + path + ": " + e.what());
    }
    openvdb::GridBase::Ptr base;
    if (file.hasGrid(name)) base = file.readGrid(name);
    file.close();
    auto grid = openvdb::gridPtrCast<GridT>(base);
    if (!grid) throw RuntimeError(path + " has no grid '" + name + "' of the expected type");
    Grid3<T> out(dims, T(0));
    auto acc = grid->getConstAccessor();
    for (int k = 0; k < dims.nz; ++k)
        for (int j = 0; j < dims.ny; ++j)
            for (int i = 0; i < dims.nx; ++i) out.at(i, j, k) = acc.getValue(openvdb::Coord(i, j, k));
    return out;
}

/// OpenVDB's archive writer, into memory: the bytes `io::File::write` would put in a file (the same
/// seekable layout), so that the one checked writer (core/atomic_file.h) puts them on disk.
class MemoryArchive : public openvdb::io::Archive {
public:
    std::string bytes(const openvdb::GridPtrVec& grids) const {
        std::ostringstream out(std::ios::out | std::ios::binary);
        openvdb::io::Archive::write(out, grids, /*seekable=*/true);
        if (!out) throw RuntimeError("OpenVDB could not encode the grids");
        return out.str();
    }
};

/// OpenVDB stamps every file with a random UUID, so two runs of the same scenario would write
/// different bytes. The UUID is the 36 characters after the header's magic number, three version
/// numbers and a flag (byte 21 on). It is replaced by one derived from the rest of the file: the
/// same grids give the same file, and different contents still get different tags. A header that
/// does not look as expected is left alone.
void makeUuidDeterministic(std::string& bytes) {
    constexpr std::size_t kAt = 21, kLen = 36;
    if (bytes.size() < kAt + kLen) return;
    for (std::size_t c = 0; c < kLen; ++c) {
        const char ch = bytes[kAt + c];
        const bool dash = c == 8 || c == 13 || c == 18 || c == 23;
        if (dash ? ch != '-' : !std::isxdigit(static_cast<unsigned char>(ch))) return;
    }
    // Two hashes of everything but the tag: the header then the grids, and the grids then the header.
    Fnv1a64 forward, backward;
    const char* head = bytes.data();
    const char* rest = bytes.data() + kAt + kLen;
    const std::size_t restBytes = bytes.size() - kAt - kLen;
    forward.add(head, kAt);
    forward.add(rest, restBytes);
    backward.add(rest, restBytes);
    backward.add(head, kAt);
    const std::uint64_t h[2] = {forward.value(), backward.value()};
    char uuid[40];
    // Version-4 layout (the "4" and the variant nibble kept), hex digits from the two hashes.
    std::snprintf(uuid, sizeof uuid, "%08llx-%04llx-4%03llx-%04llx-%012llx",
                  static_cast<unsigned long long>(h[0] >> 32), static_cast<unsigned long long>((h[0] >> 16) & 0xffff),
                  static_cast<unsigned long long>(h[0] & 0xfff),
                  static_cast<unsigned long long>(0x8000 | ((h[1] >> 48) & 0x3fff)),
                  static_cast<unsigned long long>(h[1] & 0xffffffffffffull));
    bytes.replace(kAt, kLen, uuid, kLen);
}

/// Encodes `grids` and writes them to `path` with every write checked, synced and renamed into place.
void writeGridsFile(const std::string& path, const openvdb::GridPtrVec& grids) {
    std::string bytes;
    try {
        bytes = MemoryArchive().bytes(grids);
    } catch (const std::exception& e) {
        throw RuntimeError("cannot write " + path + ": " + e.what());
    }
    makeUuidDeterministic(bytes);
    writeFileAtomic(path, bytes);
}

}  // namespace

void writeVdb(const std::string& path, const std::vector<NamedGrid>& grids, double voxelSize,
              const std::array<double, 3>& origin) {
    openvdb::initialize();
    openvdb::GridPtrVec out;
    for (const NamedGrid& ng : grids) {
        openvdb::GridBase::Ptr g;
        if (ng.floats)
            g = denseToGrid<openvdb::FloatGrid>(*ng.floats, voxelSize, origin);
        else if (ng.ints)
            g = denseToGrid<openvdb::Int32Grid>(*ng.ints, voxelSize, origin);
        else
            continue;
        g->setName(ng.name);
        g->setGridClass(openvdb::GRID_UNKNOWN);
        if (!ng.description.empty()) g->insertMeta("description", openvdb::StringMetadata(ng.description));
        out.push_back(g);
    }
    writeGridsFile(path, out);
}

Grid3<float> readVdbFloat(const std::string& path, const std::string& name, const Dims& dims) {
    return gridToDense<openvdb::FloatGrid, float>(path, name, dims);
}
Grid3<std::int32_t> readVdbInt(const std::string& path, const std::string& name, const Dims& dims) {
    return gridToDense<openvdb::Int32Grid, std::int32_t>(path, name, dims);
}

void writeExportVdb(const std::string& path, const Domain& domain, const Cave& cave, const MeshOptions& options) {
    detail::validateMeshOptions(options, domain.voxelSize);
    if (!(cave.mask.dims == domain.dims) || cave.voxelSize != domain.voxelSize)
        throw InputError("cannot write " + path + ": the cave is not on the domain's grid");
    openvdb::initialize();
    const double h = domain.voxelSize;
    openvdb::GridPtrVec out;
    auto add = [&out](openvdb::GridBase::Ptr g, const std::string& name, const std::string& description,
                      const std::string& unit) {
        g->setName(name);
        g->insertMeta("description", openvdb::StringMetadata(description));
        g->insertMeta("unit", openvdb::StringMetadata(unit));
        out.push_back(g);
    };
    auto addDense = [&](const Grid3<float>& dense, const std::string& name, const std::string& description,
                        const std::string& unit) {
        if (dense.size() != domain.dims.count()) return;  // a grid the run never filled
        auto g = denseToGrid<openvdb::FloatGrid>(dense, h);
        g->setGridClass(openvdb::GRID_UNKNOWN);
        add(g, name, description, unit);
    };
    addDense(domain.porosity, "porosity", "porosity R in [0,1] (water capacity)", "1");
    addDense(domain.porosity0, "porosity0", "initial porosity", "1");
    Grid3<float> flags(domain.dims, 0.f), zone(domain.dims, 0.f);
    for (std::size_t v = 0; v < flags.size() && v < domain.flags.size(); ++v) flags[v] = float(domain.flags[v]);
    for (std::size_t v = 0; v < zone.size() && v < domain.zone.size(); ++v) zone[v] = float(domain.zone[v]);
    addDense(flags, "flags",
             "float copy of the flag bits: 1 source, 2 sink, 4 protochannel, 8 channel, 16 obstacle, 32 fracture, "
             "64 rock.channel",
             "bits");
    addDense(zone, "zone", "float copy of the stage-1 pressure zone: source index, -1 none", "index");
    addDense(domain.pressure, "pressure", "stage-2 pressure", "1 (relative to the source pressure)");
    addDense(domain.flow, "flow", "stage-2 flow f of the last iteration (Eq. 2)", "voxel volumes per iteration");
    addDense(domain.water, "water", "stage-2 water contents", "voxel volumes");

    const detail::CaveSurface surface = detail::buildCaveSurface(cave.mask, h, options, false);
    if (surface.levelSet.grid) {
        openvdb::FloatGrid::Ptr cave = openvdb::tools::levelSetRebuild(
            *surface.levelSet.grid, float(surface.levelSet.isoValue), float(options.halfWidth));
        cave->setGridClass(openvdb::GRID_LEVEL_SET);
        add(cave, "cave", "cave surface (as cave.obj): signed distance, negative inside the cave", "m");
    }

    writeGridsFile(path, out);
}

}  // namespace cavesim::mesh
