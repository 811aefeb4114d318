#include "mesh/vdb_io.h"

#include <openvdb/openvdb.h>

#include "core/error.h"

namespace cavesim::mesh {
namespace {

openvdb::math::Transform::Ptr transformFor(double voxelSize) {
    auto xf = openvdb::math::Transform::createLinearTransform(voxelSize);
    // Index (i,j,k) is the voxel whose centre is at (i+0.5)·h.
    xf->postTranslate(openvdb::Vec3d(0.5 * voxelSize));
    return xf;
}

template <typename GridT, typename T>
typename GridT::Ptr denseToGrid(const Grid3<T>& g, double voxelSize) {
    auto grid = GridT::create(T(0));
    auto acc = grid->getAccessor();
    const Dims& d = g.dims;
    for (int k = 0; k < d.nz; ++k)
        for (int j = 0; j < d.ny; ++j)
            for (int i = 0; i < d.nx; ++i) {
                const T v = g.at(i, j, k);
                if (v != T(0)) acc.setValue(openvdb::Coord(i, j, k), v);
            }
    grid->setTransform(transformFor(voxelSize));
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

}  // namespace

void writeVdb(const std::string& path, const std::vector<NamedGrid>& grids, double voxelSize) {
    openvdb::initialize();
    openvdb::GridPtrVec out;
    for (const NamedGrid& ng : grids) {
        openvdb::GridBase::Ptr g;
        if (ng.floats) g = denseToGrid<openvdb::FloatGrid>(*ng.floats, voxelSize);
        else if (ng.ints) g = denseToGrid<openvdb::Int32Grid>(*ng.ints, voxelSize);
        else continue;
        g->setName(ng.name);
        g->setGridClass(openvdb::GRID_UNKNOWN);
        if (!ng.description.empty()) g->insertMeta("description", openvdb::StringMetadata(ng.description));
        out.push_back(g);
    }
    try {
        openvdb::io::File file(path);
        file.write(out);
        file.close();
    } catch (const openvdb::Exception& e) {
        throw RuntimeError("cannot write " + path + ": " + e.what());
    }
}

Grid3<float> readVdbFloat(const std::string& path, const std::string& name, const Dims& dims) {
    return gridToDense<openvdb::FloatGrid, float>(path, name, dims);
}
Grid3<std::int32_t> readVdbInt(const std::string& path, const std::string& name, const Dims& dims) {
    return gridToDense<openvdb::Int32Grid, std::int32_t>(path, name, dims);
}

}  // namespace cavesim::mesh
