#include "app/checkpoint.h"

#include <algorithm>
#include <cstring>

#include <tbb/parallel_for.h>
#include <zlib.h>

#include "core/bytes.h"
#include "core/check.h"
#include "core/fnv.h"
#include "sim/scenario_io.h"

namespace fs = std::filesystem;

namespace cavesim::app {
namespace {

constexpr char kMagic[16] = {'C', 'A', 'V', 'E', 'S', 'I', 'M', '-', 'C', 'H', 'E', 'C', 'K', 'P', 'T', '\n'};
/// Version 2 added the records of base-level phases to the stage-2 state; version 1 files (runs
/// without phases or a water table) are still read: their stage-2 state says which it is.
constexpr std::uint32_t kVersion = 2;
constexpr std::uint32_t kOldestVersion = 1;
constexpr std::size_t kChunk = std::size_t(4) << 20;
constexpr int kMaxFrameSide = 1 << 15;

void putOptionalString(ByteWriter& out, const std::optional<std::string>& v) {
    out.put(std::uint8_t(v ? 1 : 0));
    out.putString(v ? *v : std::string());
}

std::optional<std::string> getOptionalString(ByteReader& in, const char* what) {
    const std::uint8_t has = in.get<std::uint8_t>(what);
    std::string v = in.getString(what);
    if (has > 1) in.fail(std::string("an unreadable ") + what);
    return has ? std::optional<std::string>(std::move(v)) : std::nullopt;
}

template <typename E>
void putOptionalEnum(ByteWriter& out, const std::optional<E>& v) {
    out.put(std::int16_t(v ? int(*v) : -1));
}

template <typename E>
std::optional<E> getOptionalEnum(ByteReader& in, const char* what, int count) {
    const std::int16_t v = in.get<std::int16_t>(what);
    if (v < -1 || v >= count) in.fail(std::string("an unknown ") + what);
    return v < 0 ? std::nullopt : std::optional<E>(E(v));
}

/// A relative path this program writes into a run folder: no absolute path, no "..", plain names.
bool safeRelative(const std::string& p) {
    if (p.empty() || p.size() > 255 || p.front() == '/') return false;
    for (const fs::path& part : fs::path(p))
        if (part == ".." || part == "." || part.empty()) return false;
    return std::all_of(p.begin(), p.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
               c == '.' || c == '/';
    });
}

}  // namespace

fs::path checkpointDir(const fs::path& target) {
    std::error_code ec;
    fs::path t = fs::weakly_canonical(fs::absolute(target, ec), ec);
    if (ec || t.empty()) t = fs::absolute(target).lexically_normal();
    if (t.filename().empty()) t = t.parent_path();
    std::string name = t.filename().string();
    if (name.size() > 200) name = name.substr(0, 200);
    return t.parent_path() / ("." + name + ".checkpoint");
}

std::uint64_t scenarioHash(const Scenario& s) {
    const std::string text = scenarioToToml(s);
    Fnv1a64 h;
    h.add(text.data(), text.size());
    return h.value();
}

std::uint64_t domainFingerprint(const Domain& d) {
    Fnv1a64 h;
    h.add(d.porosity.data.data(), d.porosity.data.size() * sizeof(float));
    h.add(d.porosity0.data.data(), d.porosity0.data.size() * sizeof(float));
    h.add(d.flags.data.data(), d.flags.data.size());
    h.add(d.zone.data.data(), d.zone.data.size() * sizeof(std::int32_t));
    // Stage 2 reads these too, and a [site] reads them from files (a sinkhole's pressure, the
    // water table of `from_site`) that may change between a run and its resume.
    h.add(d.sourcePressure.data(), d.sourcePressure.size() * sizeof(double));
    h.add(d.siteWaterTable.data(), d.siteWaterTable.size() * sizeof(double));
    return h.value();
}

void checkResumedDomain(std::uint64_t domainHash, const Checkpoint& resume, const std::string& shown,
                        const std::string& advice) {
    if (domainHash != resume.domainHash)
        throw InputError(shown +
                         ": the domain at the start of stage 2 is not the one the checkpoint was made from (a "
                         "file the scenario reads changed, or another version of cavesim); " +
                         advice);
}

std::string encodeCheckpoint(const Checkpoint& c) {
    std::string payload;
    ByteWriter out(payload);
    out.putString(c.scenarioPath);
    out.putString(c.scenarioText);
    putOptionalString(out, c.seed);
    putOptionalString(out, c.formats);
    putOptionalEnum(out, c.meshStyle);
    putOptionalEnum(out, c.meshNormals);
    out.put(std::uint8_t(c.force ? 1 : 0));
    out.put(std::int32_t(c.every));
    out.put(c.scenarioHash);
    out.put(c.domainHash);
    out.put(std::int32_t(c.iteration));
    out.put(std::uint64_t(c.files.size()));
    for (const auto& [path, bytes] : c.files) {
        CAVESIM_CHECK(safeRelative(path), "checkpoint file name " + path);
        out.putString(path);
        out.putString(bytes);
    }
    out.put(std::uint64_t(c.frames.size()));
    for (const render::Image& f : c.frames) {
        out.put(std::int32_t(f.width));
        out.put(std::int32_t(f.height));
        out.putVector(f.pixels);
    }
    out.putString(c.stage2);

    const std::size_t chunks = (payload.size() + kChunk - 1) / kChunk;
    std::vector<std::string> packed(chunks);
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
        const std::size_t begin = k * kChunk, count = std::min(kChunk, payload.size() - begin);
        uLongf length = compressBound(uLong(count));
        std::string buf(length, '\0');
        const int rc = ::compress2(reinterpret_cast<Bytef*>(buf.data()), &length,
                                   reinterpret_cast<const Bytef*>(payload.data() + begin), uLong(count), 1);
        CAVESIM_CHECK(rc == Z_OK, "zlib cannot compress a checkpoint chunk");
        buf.resize(length);
        packed[k] = std::move(buf);
    });
    std::string file(kMagic, sizeof kMagic);
    ByteWriter head(file);
    head.put(kVersion);
    head.put(std::uint64_t(payload.size()));
    head.put(std::uint32_t(chunks));
    for (std::size_t k = 0; k < chunks; ++k) {
        head.put(std::uint32_t(std::min(kChunk, payload.size() - k * kChunk)));
        head.put(std::uint32_t(packed[k].size()));
        file += packed[k];
    }
    Fnv1a64 hp;
    hp.add(payload.data(), payload.size());
    head.put(hp.value());
    Fnv1a64 hf;
    hf.add(file.data(), file.size());
    head.put(hf.value());
    return file;
}

Checkpoint decodeCheckpoint(const std::string& bytes, const std::string& shown) {
    ByteReader file(bytes.data(), bytes.size() >= 8 ? bytes.size() - 8 : 0, shown);
    if (bytes.size() < sizeof kMagic + 8) file.fail("too short: cut, or not a checkpoint");
    if (std::memcmp(file.take(sizeof kMagic, "the magic number"), kMagic, sizeof kMagic) != 0)
        file.fail("no checkpoint magic number");
    std::uint64_t recorded;
    std::memcpy(&recorded, bytes.data() + bytes.size() - 8, 8);
    Fnv1a64 hf;
    hf.add(bytes.data(), bytes.size() - 8);
    if (hf.value() != recorded) file.fail("a file checksum that does not match its bytes: cut or changed");
    const std::uint32_t version = file.get<std::uint32_t>("the version");
    if (version < kOldestVersion || version > kVersion)
        file.fail("checkpoint format version " + std::to_string(version) + "; this program reads versions " +
                  std::to_string(kOldestVersion) + " to " + std::to_string(kVersion));
    const std::uint64_t size = file.get<std::uint64_t>("the payload size");
    const std::uint32_t chunks = file.get<std::uint32_t>("the chunk count");
    if (size > (std::uint64_t(1) << 40) || chunks != (size + kChunk - 1) / kChunk) file.fail("inconsistent sizes");
    // Each chunk unpacks into at most kChunk bytes; the payload grows only as chunks check out.
    std::string payload;
    for (std::uint32_t k = 0; k < chunks; ++k) {
        const std::uint32_t raw = file.get<std::uint32_t>("a chunk header");
        const std::uint32_t packed = file.get<std::uint32_t>("a chunk header");
        if (raw != std::min<std::uint64_t>(kChunk, size - std::uint64_t(k) * kChunk)) file.fail("a chunk size");
        const char* src = file.take(packed, "compressed data");
        const std::size_t at = payload.size();
        payload.resize(at + raw);
        uLongf length = raw;
        const int rc = ::uncompress(reinterpret_cast<Bytef*>(payload.data() + at), &length,
                                    reinterpret_cast<const Bytef*>(src), uLong(packed));
        if (rc != Z_OK || length != raw) file.fail("compressed data that does not unpack");
    }
    const std::uint64_t sum = file.get<std::uint64_t>("the payload checksum");
    if (file.left() != 0) file.fail("bytes after the payload");
    Fnv1a64 hp;
    hp.add(payload.data(), payload.size());
    if (hp.value() != sum) file.fail("a payload whose bytes do not match their checksum");

    ByteReader in(payload.data(), payload.size(), shown);
    Checkpoint c;
    c.scenarioPath = in.getString("the scenario path");
    c.scenarioText = in.getString("the scenario text");
    c.seed = getOptionalString(in, "seed");
    c.formats = getOptionalString(in, "format list");
    c.meshStyle = getOptionalEnum<MeshStyle>(in, "mesh style", 2);
    c.meshNormals = getOptionalEnum<MeshNormals>(in, "mesh normals choice", 2);
    const std::uint8_t force = in.get<std::uint8_t>("the force flag");
    if (force > 1) in.fail("an unreadable force flag");
    c.force = force == 1;
    c.every = in.get<std::int32_t>("the checkpoint interval");
    c.scenarioHash = in.get<std::uint64_t>("the scenario hash");
    c.domainHash = in.get<std::uint64_t>("the domain fingerprint");
    c.iteration = in.get<std::int32_t>("the iteration");
    if (c.every < 1 || c.iteration < 1) in.fail("an iteration out of range");
    const std::uint64_t files = in.get<std::uint64_t>("the file count");
    if (files > 4096) in.fail("too many files");
    for (std::uint64_t k = 0; k < files; ++k) {
        std::string path = in.getString("a file name");
        if (!safeRelative(path)) in.fail("a file name this program does not write");
        std::string data = in.getString("a file");
        c.files.emplace_back(std::move(path), std::move(data));
    }
    const std::uint64_t frames = in.get<std::uint64_t>("the frame count");
    if (frames > 4096) in.fail("too many frames");
    for (std::uint64_t k = 0; k < frames; ++k) {
        render::Image f;
        f.width = in.get<std::int32_t>("a frame size");
        f.height = in.get<std::int32_t>("a frame size");
        if (f.width < 1 || f.height < 1 || f.width > kMaxFrameSide || f.height > kMaxFrameSide)
            in.fail("a frame size out of range");
        in.getVector(f.pixels, "a frame", std::size_t(f.width) * std::size_t(f.height) * 3);
        c.frames.push_back(std::move(f));
    }
    c.stage2 = in.getString("the stage-2 state");
    if (in.left() != 0) in.fail("bytes after the checkpoint");
    return c;
}

}  // namespace cavesim::app
