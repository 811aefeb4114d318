#include "app/state_file.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <tbb/parallel_for.h>
#include <zlib.h>

#include "core/bytes.h"
#include "core/check.h"
#include "core/error.h"
#include "core/fnv.h"

namespace cavesim::app {
namespace {

constexpr char kMagic[16] = {'C', 'A', 'V', 'E', 'S', 'I', 'M', '-', 'S', 'T', 'A', 'T', 'E', '\n', 0, 0};
constexpr std::uint32_t kVersion = 1;
constexpr std::uint8_t kFloat = 1, kInt = 2;

/// Bounds-checked reading from the file's bytes: every read names what it wanted when it runs out.
ByteReader stateReader(const std::string& bytes, std::size_t end, const std::string& shown) {
    return ByteReader(bytes.data(), end, shown, "not a state file this program wrote, or damaged",
                      "; rerun `cavesim run`");
}

template <typename T>
void decodeValues(ByteReader& in, std::vector<T>& out, std::size_t count) {
    const std::uint32_t chunks = in.get<std::uint32_t>("a chunk count");
    const std::uint64_t sum = in.get<std::uint64_t>("a grid checksum");
    const std::size_t wanted = (count + kStateChunkValues - 1) / kStateChunkValues;
    if (chunks != wanted)
        in.fail("a grid of " + std::to_string(count) + " voxels in " + std::to_string(chunks) + " chunks");
    out.assign(count, T(0));
    std::size_t done = 0;
    for (std::uint32_t c = 0; c < chunks; ++c) {
        const std::uint32_t values = in.get<std::uint32_t>("a chunk header");
        const std::uint32_t packed = in.get<std::uint32_t>("a chunk header");
        const std::size_t expected = std::min<std::size_t>(kStateChunkValues, count - done);
        if (values != expected) in.fail("a chunk of " + std::to_string(values) + " values");
        const char* src = in.take(packed, "compressed data");
        uLongf length = uLongf(values * sizeof(T));
        const int rc = ::uncompress(reinterpret_cast<Bytef*>(out.data() + done), &length,
                                    reinterpret_cast<const Bytef*>(src), uLong(packed));
        if (rc != Z_OK || length != values * sizeof(T)) in.fail("compressed data that does not unpack");
        done += values;
    }
    Fnv1a64 h;
    h.add(out.data(), out.size() * sizeof(T));
    if (h.value() != sum) in.fail("a grid whose values do not match their checksum");
}

template <typename T>
void encodeValues(std::string& out, const std::vector<T>& values) {
    ByteWriter w(out);
    const std::size_t n = values.size();
    const std::size_t chunks = (n + kStateChunkValues - 1) / kStateChunkValues;
    std::vector<std::string> packed(chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t c) {
        const std::size_t begin = c * kStateChunkValues, count = std::min<std::size_t>(kStateChunkValues, n - begin);
        uLongf length = compressBound(uLong(count * sizeof(T)));
        std::string buf(length, '\0');
        const int rc = ::compress2(reinterpret_cast<Bytef*>(buf.data()), &length,
                                   reinterpret_cast<const Bytef*>(values.data() + begin), uLong(count * sizeof(T)), 1);
        CAVESIM_CHECK(rc == Z_OK, "zlib cannot compress a state chunk");
        buf.resize(length);
        packed[c] = std::move(buf);
    });
    Fnv1a64 h;
    h.add(values.data(), n * sizeof(T));
    w.put(std::uint32_t(chunks));
    w.put(h.value());
    for (std::size_t c = 0; c < chunks; ++c) {
        w.put(std::uint32_t(std::min<std::size_t>(kStateChunkValues, n - c * kStateChunkValues)));
        w.put(std::uint32_t(packed[c].size()));
        out += packed[c];
    }
}

bool validName(const std::string& name) {
    return !name.empty() && name.size() <= 32 && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
    });
}

}  // namespace

std::string encodeState(const Dims& dims, double voxelSize, const std::vector<StateGridRef>& grids) {
    CAVESIM_CHECK(grids.size() <= std::size_t(kMaxStateGrids), "too many grids for a state file");
    std::string out(kMagic, sizeof kMagic);
    ByteWriter w(out);
    w.put(kVersion);
    w.put(std::uint32_t(dims.nx));
    w.put(std::uint32_t(dims.ny));
    w.put(std::uint32_t(dims.nz));
    w.put(voxelSize);
    w.put(std::uint32_t(grids.size()));
    for (const StateGridRef& g : grids) {
        CAVESIM_CHECK(validName(g.name) && (g.floats != nullptr) != (g.ints != nullptr), "bad state grid " + g.name);
        CAVESIM_CHECK(g.floats ? g.floats->dims == dims : g.ints->dims == dims,
                      "state grid " + g.name + " is not on the grid");
        w.put(std::uint8_t(g.name.size()));
        out += g.name;
        w.put(g.floats ? kFloat : kInt);
        if (g.floats)
            encodeValues(out, g.floats->data);
        else
            encodeValues(out, g.ints->data);
    }
    Fnv1a64 h;
    h.add(out.data(), out.size());
    w.put(h.value());
    return out;
}

StateContents decodeState(const std::string& bytes, const std::string& shown, const Dims& expected,
                          std::size_t maxVoxels) {
    if (bytes.size() < sizeof kMagic + 8) stateReader(bytes, 0, shown).fail("too short");
    const std::size_t body = bytes.size() - 8;
    ByteReader in = stateReader(bytes, body, shown);
    if (std::memcmp(in.take(sizeof kMagic, "the magic number"), kMagic, sizeof kMagic) != 0)
        in.fail("no state-file magic number");
    std::uint64_t recorded;
    std::memcpy(&recorded, bytes.data() + body, 8);
    Fnv1a64 h;
    h.add(bytes.data(), body);
    if (h.value() != recorded) in.fail("a file checksum that does not match its bytes");
    if (in.get<std::uint32_t>("the version") != kVersion) in.fail("an unknown version");
    StateContents s;
    const std::uint32_t nx = in.get<std::uint32_t>("the grid size"), ny = in.get<std::uint32_t>("the grid size"),
                        nz = in.get<std::uint32_t>("the grid size");
    s.voxelSize = in.get<double>("the voxel size");
    if (nx == 0 || ny == 0 || nz == 0 || nx > (1u << 16) || ny > (1u << 16) || nz > (1u << 16))
        in.fail("a grid of " + std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) +
                " voxels");
    s.dims = Dims{int(nx), int(ny), int(nz)};
    const bool anyGrid = expected.count() == 0;
    if (anyGrid ? s.dims.count() > maxVoxels : !(s.dims == expected))
        in.fail("a grid of " + std::to_string(nx) + " x " + std::to_string(ny) + " x " + std::to_string(nz) +
                " voxels where the scenario says otherwise");
    if (!std::isfinite(s.voxelSize) || s.voxelSize <= 0) in.fail("a voxel size that is not a positive number");
    const std::uint32_t n = in.get<std::uint32_t>("the number of grids");
    if (n > std::uint32_t(kMaxStateGrids)) in.fail(std::to_string(n) + " grids");
    for (std::uint32_t g = 0; g < n; ++g) {
        StateGrid grid;
        const std::uint8_t len = in.get<std::uint8_t>("a grid name");
        grid.name.assign(in.take(len, "a grid name"), len);
        if (!validName(grid.name)) in.fail("a grid name that is not one this program writes");
        for (const StateGrid& other : s.grids)
            if (other.name == grid.name) in.fail("grid '" + grid.name + "' twice");
        const std::uint8_t type = in.get<std::uint8_t>("a grid type");
        if (type != kFloat && type != kInt) in.fail("an unknown grid type");
        grid.isFloat = type == kFloat;
        if (grid.isFloat) {
            grid.floats.dims = s.dims;
            decodeValues(in, grid.floats.data, s.dims.count());
        } else {
            grid.ints.dims = s.dims;
            decodeValues(in, grid.ints.data, s.dims.count());
        }
        s.grids.push_back(std::move(grid));
    }
    if (in.at() != body) in.fail("bytes after the last grid");
    return s;
}

}  // namespace cavesim::app
