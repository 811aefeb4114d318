#include "formats/vtk_formats.h"

#include <cstdint>
#include <sstream>
#include <string_view>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "formats/detail.h"
#include "formats/passages.h"
#include "sim/cave.h"

namespace cavesim::formats {
namespace {

// One ASCII String array of VTK XML: character codes, each string ended by 0.
std::string stringArray(const std::string& name, const std::vector<std::string>& values) {
    std::string s = "      <Array type=\"String\" Name=\"" + name + "\" NumberOfTuples=\"" +
                    std::to_string(values.size()) + "\" format=\"ascii\">\n        ";
    for (const std::string& v : values) {
        for (unsigned char c : v) s += std::to_string(int(c)) + " ";
        s += "0 ";
    }
    s += "\n      </Array>\n";
    return s;
}

// `extra`: more arrays, after the voxel size.
std::string fieldData(const std::vector<std::string>& units, double voxelSize, const std::string& extra = "") {
    std::string s = "    <FieldData>\n";
    s += stringArray("units", units);
    s += stringArray("length_unit", {"m"});
    s += stringArray("axes", {"world space, metres: x east, y north, z up"});
    if (voxelSize > 0)
        s += "      <DataArray type=\"Float64\" Name=\"voxel_size_m\" NumberOfTuples=\"1\" format=\"ascii\">" +
             detail::num(voxelSize) + "</DataArray>\n";
    s += extra;
    s += "    </FieldData>\n";
    return s;
}

std::string originText(const std::array<double, 3>& origin) {
    return detail::num(origin[0]) + " " + detail::num(origin[1]) + " " + detail::num(origin[2]);
}

/// The XML around an ImageData file's appended data: `head` ends with the "_" that starts it,
/// `tail` closes the file; the appended bytes go between them.
struct ImageXml {
    std::string head, tail;
};

// The XML of a VTK XML ImageData file of the cells of `d` (voxel edge `voxelSize` metres, low
// corner at `origin`): `cellArrays` (DataArray elements, `scalars` the active one) whose values
// are the raw appended block written between its head and tail.

ImageXml imageData(const Dims& d, const std::string& origin, double voxelSize, const std::string& fields,
                   const std::string& scalars, const std::string& cellArrays) {
    const std::string h = detail::num(voxelSize);
    const std::string extent =
        "0 " + std::to_string(d.nx) + " 0 " + std::to_string(d.ny) + " 0 " + std::to_string(d.nz);
    ImageXml xml;
    xml.head += "<?xml version=\"1.0\"?>\n";
    xml.head += "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n";
    xml.head += "  <ImageData WholeExtent=\"" + extent + "\" Origin=\"" + origin + "\" Spacing=\"" + h + " " + h + " " +
                h + "\">\n";
    xml.head += fields;
    xml.head += "    <Piece Extent=\"" + extent + "\">\n      <PointData>\n      </PointData>\n";
    xml.head += "      <CellData Scalars=\"" + scalars + "\">\n" + cellArrays + "      </CellData>\n    </Piece>\n";
    xml.head += "  </ImageData>\n  <AppendedData encoding=\"raw\">\n   _";
    xml.tail = "\n  </AppendedData>\n</VTKFile>\n";
    return xml;
}

/// The bytes of a grid's values, where they lie.
template <typename T>
std::string_view bytesOf(const std::vector<T>& v) {
    return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
}

template <typename T>
struct VtkType;
template <>
struct VtkType<float> {
    static constexpr const char* name = "Float32";
};
template <>
struct VtkType<std::uint8_t> {
    static constexpr const char* name = "UInt8";
};
template <>
struct VtkType<std::int32_t> {
    static constexpr const char* name = "Int32";
};

}  // namespace

void writeStateVti(const Domain& domain, const std::string& path, const Cave* cave) {
    const Dims& d = domain.dims;
    if (d.count() == 0) throw RuntimeError("cannot write " + path + ": the domain has no voxels");
    // Each array is its 8-byte size and its values, written from the grids where they lie: the file
    // needs no copy of the grids in memory (26 bytes a voxel at 10⁸ voxels would be 2.6 GB).
    std::string arrays;
    std::vector<std::string> units;
    std::vector<std::uint64_t> sizes;  // each array's size prefix
    std::vector<std::string_view> values;
    std::uint64_t offset = 0;
    auto add = [&](const auto& grid, const std::string& name, const std::string& unit) {
        using T = typename std::decay_t<decltype(grid.data)>::value_type;
        if (grid.size() != d.count()) return;
        arrays += "        <DataArray type=\"" + std::string(VtkType<T>::name) + "\" Name=\"" + name +
                  "\" NumberOfComponents=\"1\" format=\"appended\" offset=\"" + std::to_string(offset) + "\"/>\n";
        sizes.push_back(std::uint64_t(grid.size() * sizeof(T)));
        values.push_back(bytesOf(grid.data));
        offset += sizeof(std::uint64_t) + sizes.back();
        units.push_back(name + ": " + unit);
    };
    add(domain.porosity, "porosity", "1 (fraction of the voxel that holds water)");
    add(domain.porosity0, "porosity0", "1 (initial porosity)");
    add(domain.flags, "flags",
        "bits: 1 source, 2 sink, 4 protochannel, 8 channel, 16 obstacle, 32 fracture, 64 rock.channel, 128 inert "
        "(site: air or insoluble)");
    add(domain.zone, "zone", "index (stage-1 zone: source index, -1 none)");
    add(domain.pressure, "pressure", "1 (stage-2 pressure, relative to the source pressure)");
    add(domain.flow, "flow", "voxel volumes per iteration (stage-2 flow f of the last iteration)");
    add(domain.water, "water", "voxel volumes (stage-2 water contents)");
    if (cave) {
        if (!(cave->mask.dims == d))
            throw RuntimeError("cannot write " + path + ": the cave is not on the domain's grid");
        add(cave->mask, "cave", "1 = cave voxel, 0 = rock");
    }
    const ImageXml xml = imageData(d, originText(domain.origin), domain.voxelSize, fieldData(units, domain.voxelSize),
                                   "porosity", arrays);
    std::vector<std::string_view> pieces{xml.head};
    for (std::size_t a = 0; a < values.size(); ++a) {
        pieces.push_back({reinterpret_cast<const char*>(&sizes[a]), sizeof(std::uint64_t)});
        pieces.push_back(values[a]);
    }
    pieces.push_back(xml.tail);
    writeFileAtomic(path, pieces);
}

void writeScalarVti(const Grid3<float>& grid, const std::string& name, const std::string& unit, double voxelSize,
                    const std::array<double, 3>& origin, const std::string& path) {
    const Dims& d = grid.dims;
    if (d.count() == 0 || grid.size() != d.count()) throw RuntimeError("cannot write " + path + ": an empty grid");
    const std::uint64_t size = std::uint64_t(grid.size() * sizeof(float));
    const std::string o = originText(origin);
    const std::string fields =
        fieldData({name + ": " + unit}, voxelSize,
                  "      <DataArray type=\"Float64\" Name=\"world_origin_m\" NumberOfTuples=\"1\" "
                  "NumberOfComponents=\"3\" format=\"ascii\">" +
                      o + "</DataArray>\n");
    const ImageXml xml = imageData(d, o, voxelSize, fields, name,
                                   "        <DataArray type=\"Float32\" Name=\"" + name +
                                       "\" NumberOfComponents=\"1\" format=\"appended\" offset=\"0\"/>\n");
    writeFileAtomic(path, {xml.head, std::string_view(reinterpret_cast<const char*>(&size), sizeof size),
                           bytesOf(grid.data), xml.tail});
}

void writeSkeletonVtp(const morpho::Skeleton& skeleton, const std::string& path, const Domain* domain) {
    const std::vector<morpho::Branch> passages = findPassages(skeleton);
    const std::size_t n = skeleton.nodes.size();
    const std::vector<int> passageOf = passageOfNodes(skeleton, passages);
    std::vector<int> degree(n, 0);
    for (const auto& e : skeleton.edges) {
        ++degree[std::size_t(e[0])];
        ++degree[std::size_t(e[1])];
    }
    const bool withFields =
        domain && domain->flow.size() == domain->dims.count() && domain->pressure.size() == domain->dims.count();
    if (withFields)
        for (const auto& node : skeleton.nodes)
            if (node.voxel >= domain->dims.count())
                throw RuntimeError("cannot write " + path + ": a skeleton node stands on voxel " +
                                   std::to_string(node.voxel) + ", outside the domain");

    std::ostringstream x;
    auto beginArray = [&x](const char* type, const char* name, int components = 1) {
        x << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\" NumberOfComponents=\"" << components
          << "\" format=\"ascii\">\n         ";
    };
    auto endArray = [&x] { x << "\n        </DataArray>\n"; };
    std::vector<std::string> units{"radius: m (node to the nearest wall)",
                                   "passage_id: index (first passage through the node; -1 none)",
                                   "degree: count (skeleton edges at the node)", "length_m: m (passage length)"};
    if (withFields) {
        units.push_back("flow: voxel volumes per iteration (stage-2 flow at the node's voxel)");
        units.push_back("pressure: 1 (stage-2 pressure at the node's voxel, relative to the source pressure)");
    }
    x << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      << "  <PolyData>\n"
      << fieldData(units, domain ? domain->voxelSize : 0.0) << "    <Piece NumberOfPoints=\"" << n
      << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << passages.size()
      << "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n"
      << "      <PointData Scalars=\"radius\">\n";
    beginArray("Float64", "radius");
    for (const auto& node : skeleton.nodes) x << ' ' << detail::num(node.radius);
    endArray();
    beginArray("Int32", "passage_id");
    for (int p : passageOf) x << ' ' << p;
    endArray();
    beginArray("Int32", "degree");
    for (int g : degree) x << ' ' << g;
    endArray();
    if (withFields) {
        beginArray("Float32", "flow");
        for (const auto& node : skeleton.nodes) x << ' ' << detail::num(domain->flow[node.voxel]);
        endArray();
        beginArray("Float32", "pressure");
        for (const auto& node : skeleton.nodes) x << ' ' << detail::num(domain->pressure[node.voxel]);
        endArray();
    }
    x << "      </PointData>\n      <CellData Scalars=\"passage_id\">\n";
    beginArray("Int32", "passage_id");
    for (std::size_t p = 0; p < passages.size(); ++p) x << ' ' << p;
    endArray();
    beginArray("Float64", "length_m");
    for (const auto& p : passages) x << ' ' << detail::num(p.length_m);
    endArray();
    x << "      </CellData>\n      <Points>\n";
    beginArray("Float64", "Points", 3);
    for (const auto& node : skeleton.nodes)
        x << "  " << detail::num(node.position[0]) << ' ' << detail::num(node.position[1]) << ' '
          << detail::num(node.position[2]);
    endArray();
    x << "      </Points>\n      <Lines>\n";
    beginArray("Int64", "connectivity");
    for (const auto& p : passages)
        for (int v : p.nodes) x << ' ' << v;
    endArray();
    beginArray("Int64", "offsets");
    std::size_t offset = 0;
    for (const auto& p : passages) x << ' ' << (offset += p.nodes.size());
    endArray();
    x << "      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n";
    writeFileAtomic(path, x.str());
}

}  // namespace cavesim::formats
