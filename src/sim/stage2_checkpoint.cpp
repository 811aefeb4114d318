#include "sim/stage2_checkpoint.h"

#include <algorithm>
#include <cmath>

namespace cavesim::stage2 {
namespace {

constexpr std::uint32_t kCarryMagic = 0x33455453;    // "STE3": with the phase records
constexpr std::uint32_t kCarryMagicV1 = 0x32455453;  // "STE2": checkpoint format version 1, no phases

void putOptional(ByteWriter& out, const std::optional<int>& v) {
    out.put(std::uint8_t(v ? 1 : 0));
    out.put(std::int32_t(v ? *v : 0));
}

std::optional<int> getOptional(ByteReader& in, const char* what) {
    const std::uint8_t has = in.get<std::uint8_t>(what);
    const std::int32_t v = in.get<std::int32_t>(what);
    if (has > 1) in.fail(std::string("an unreadable ") + what);
    return has ? std::optional<int>(v) : std::nullopt;
}

template <typename T>
void getGrid(ByteReader& in, Grid3<T>& grid, const Dims& dims, const char* what) {
    grid.dims = dims;
    in.getVector(grid.data, what, dims.count());
}

void putList(ByteWriter& out, const std::vector<int>& list) {
    out.put(std::uint64_t(list.size()));
    for (int x : list) out.put(std::int32_t(x));
}

/// A 1-based list of at most `count` distinct terminals in increasing order (what activeList gives).
std::vector<int> getList(ByteReader& in, std::size_t count, const char* what) {
    const std::uint64_t size = in.get<std::uint64_t>(what);
    if (size > count) in.fail(std::string("too many entries in ") + what);
    std::vector<int> list;
    for (std::uint64_t k = 0; k < size; ++k) {
        const std::int32_t x = in.get<std::int32_t>(what);
        if (x < 1 || std::size_t(x) > count || (!list.empty() && x <= list.back()))
            in.fail(std::string("an entry out of range in ") + what);
        list.push_back(x);
    }
    return list;
}

void putPhase(ByteWriter& out, const Stage2PhaseRecord& p) {
    out.put(std::int32_t(p.firstIteration));
    out.put(std::int32_t(p.iterations));
    out.put(p.waterTable);
    out.put(std::uint8_t(p.fromSite ? 1 : 0));
    putList(out, p.sinks);
    putList(out, p.sources);
    putOptional(out, p.breakthroughIteration);
    for (long x : {p.channelVoxelsStart, p.channelVoxelsEnd, p.caveBelow, p.caveAbove}) out.put(std::int64_t(x));
    for (const std::array<int, 3>* box : {&p.aboveLo, &p.aboveHi, &p.belowLo, &p.belowHi})
        for (int x : *box) out.put(std::int32_t(x));
    for (double x : {p.aboveSliceMean, p.injected, p.drained, p.eroded}) out.put(x);
}

/// A phase record of a run after `iterations` iterations on `dom`: checks what could index or
/// count anything (runStage2 checks the rest against the scenario's phases).
Stage2PhaseRecord getPhase(ByteReader& in, const Domain& dom, int iterations) {
    Stage2PhaseRecord p;
    p.firstIteration = in.get<std::int32_t>("a phase record");
    p.iterations = in.get<std::int32_t>("a phase record");
    if (p.firstIteration < 0 || p.firstIteration > iterations || p.iterations < 0 || p.iterations > iterations)
        in.fail("a phase record out of range");
    p.waterTable = in.get<double>("a phase record");
    const std::uint8_t fromSite = in.get<std::uint8_t>("a phase record");
    if (fromSite > 1 || !std::isfinite(p.waterTable)) in.fail("an unreadable phase record");
    p.fromSite = fromSite == 1;
    p.sinks = getList(in, dom.sinkVoxels.size(), "the sinks of a phase");
    p.sources = getList(in, dom.sourceVoxels.size(), "the sources of a phase");
    p.breakthroughIteration = getOptional(in, "a phase record");
    for (long* x : {&p.channelVoxelsStart, &p.channelVoxelsEnd, &p.caveBelow, &p.caveAbove}) {
        const std::int64_t v = in.get<std::int64_t>("a phase record");
        if (v < 0 || std::uint64_t(v) > dom.dims.count()) in.fail("a voxel count out of range in a phase record");
        *x = long(v);
    }
    for (std::array<int, 3>* box : {&p.aboveLo, &p.aboveHi, &p.belowLo, &p.belowHi})
        for (int& x : *box) x = in.get<std::int32_t>("a phase record");
    for (double* x : {&p.aboveSliceMean, &p.injected, &p.drained, &p.eroded}) {
        *x = in.get<double>("a phase record");
        if (!std::isfinite(*x)) in.fail("a phase total that is not a finite number");
    }
    return p;
}

}  // namespace

void saveState(ByteWriter& out, const Stage2State& st) {
    out.putVector(st.water);
    out.putVector(st.tileSlot);
    out.putVector(st.activeTiles);
    out.putVector(st.tileWet);
    out.putVector(st.wetNow);
    out.putVector(st.waterChanged);
    out.putVector(st.pressureTop);
    out.putVector(st.nearSender);
    out.putVector(st.senderMask);
    out.putVector(st.workMask);
    out.putVector(st.previousMask);
    for (const std::vector<double>* f :
         {&st.norm, &st.scale, &st.incoming, &st.accept, &st.fc, &st.fa, &st.upShare, &st.drainedHere, &st.erodedHere})
        out.putVector(*f);
    out.put(std::int64_t(st.channelVoxels));
    out.putBools(st.reached);
}

void restoreState(ByteReader& in, Stage2State& st) {
    const std::size_t voxels = st.dims.count(), tiles = st.tileSlot.size();
    in.getVector(st.water, "the water contents", voxels);
    in.getVector(st.tileSlot, "the tile slots", tiles);
    in.getVector(st.activeTiles, "the active tiles");
    const std::size_t slots = st.activeTiles.size();
    if (slots > tiles) in.fail("more active tiles than tiles");
    std::size_t active = 0;
    for (std::int32_t s : st.tileSlot) {
        if (s < -1 || s >= std::int32_t(slots)) in.fail("a tile slot out of range");
        active += s >= 0 ? 1 : 0;
    }
    if (active != slots) in.fail("tile slots that do not match the active tiles");
    for (std::size_t s = 0; s < slots; ++s)
        if (st.activeTiles[s] >= tiles || st.tileSlot[st.activeTiles[s]] != std::int32_t(s))
            in.fail("tile slots that do not match the active tiles");
    in.getVector(st.tileWet, "the wet tiles", tiles);
    in.getVector(st.wetNow, "the wet slots", slots);
    in.getVector(st.waterChanged, "the changed slots", slots);
    in.getVector(st.pressureTop, "the pressure bounds", slots);
    in.getVector(st.nearSender, "the working slots", slots);
    in.getVector(st.senderMask, "the sender masks", slots);
    in.getVector(st.workMask, "the work masks", slots);
    in.getVector(st.previousMask, "the previous masks", slots);
    // A mask may only name voxels of its tile inside the grid (the loops over masks trust them).
    for (std::size_t s = 0; s < slots; ++s) {
        const std::uint32_t t = st.activeTiles[s];
        const int ti = int(t % std::uint32_t(st.tilesX)),
                  tj = int((t / std::uint32_t(st.tilesX)) % std::uint32_t(st.tilesY)),
                  tk = int(t / (std::uint32_t(st.tilesX) * std::uint32_t(st.tilesY)));
        const int ni = std::min(kTileSize, st.dims.nx - ti * kTileSize),
                  nj = std::min(kTileSize, st.dims.ny - tj * kTileSize),
                  nk = std::min(kTileSize, st.dims.nz - tk * kTileSize);
        for (std::size_t r = 0; r < 64; ++r) {
            const unsigned inside = int(r & 7) < nj && int(r >> 3) < nk ? (1u << ni) - 1u : 0u;
            for (const std::vector<TileMask>* m : {&st.senderMask, &st.workMask, &st.previousMask})
                if ((*m)[s][r] & ~inside) in.fail("a tile mask naming voxels outside the grid");
        }
    }
    for (std::vector<double>* f :
         {&st.norm, &st.scale, &st.incoming, &st.accept, &st.fc, &st.fa, &st.upShare, &st.drainedHere, &st.erodedHere})
        in.getVector(*f, "a transient of the active tiles", slots * kTileVoxels);
    st.channelVoxels = long(in.get<std::int64_t>("the channel count"));
    in.getBools(st.reached, "the reach of the sinks", voxels);
    st.refreshTiles();
    st.recountWater();
}

std::string encodeCarry(const Carry& c, const Domain& dom) {
    std::string bytes;
    ByteWriter out(bytes);
    out.put(kCarryMagic);
    out.put(std::uint32_t(dom.dims.nx));
    out.put(std::uint32_t(dom.dims.ny));
    out.put(std::uint32_t(dom.dims.nz));
    out.put(std::int32_t(c.iteration));
    // The result so far, field by field (no padding bytes in the file).
    const Stage2Result& r = c.result;
    out.put(std::int32_t(r.iterations));
    putOptional(out, r.breakthroughIteration);
    out.put(std::uint64_t(r.sourceConnectedIteration.size()));
    for (const std::optional<int>& v : r.sourceConnectedIteration) putOptional(out, v);
    for (double x : {r.waterBalanceRelError, r.totalInjected, r.totalDrained, r.pressureCap, r.seconds,
                     r.pressureSeconds, r.transportSeconds, r.erosionSeconds, r.workedVoxelIterations})
        out.put(x);
    out.putVector(r.sourceInjected);
    out.put(std::uint64_t(r.history.size()));
    for (const Stage2Record& h : r.history) {
        out.put(std::int32_t(h.iteration));
        for (double x : {h.injected, h.drained, h.stored, h.flow, h.eroded, h.balanceError}) out.put(x);
        out.put(std::int64_t(h.channelVoxels));
        out.put(std::int64_t(h.pressureUpdates));
        out.put(std::int32_t(h.sourcesConnected));
    }
    out.put(std::uint64_t(r.phases.size()));
    for (const Stage2PhaseRecord& p : r.phases) putPhase(out, p);
    putPhase(out, c.phase);
    out.put(std::uint64_t(c.refill.size()));
    for (const Refill& f : c.refill) {
        out.put(std::uint64_t(f.voxel));
        out.put(f.level);
        out.put(std::int32_t(f.source));
        out.put(f.head);
    }
    out.put(c.stored);
    out.putVector(c.rate.data);
    c.pressure.save(out);
    saveState(out, c.state);
    // The domain grids stage 2 changes.
    out.putVector(dom.porosity.data);
    out.putVector(dom.flags.data);
    out.putVector(dom.flow.data);
    out.putVector(dom.water.data);
    out.putVector(dom.pressure.data);
    return bytes;
}

void decodeCarry(const std::string& bytes, const std::string& shown, Carry& c, Domain& dom) {
    ByteReader in(bytes.data(), bytes.size(), shown);
    const Dims& d = dom.dims;
    const std::uint32_t magic = in.get<std::uint32_t>("the stage-2 state");
    if (magic != kCarryMagic && magic != kCarryMagicV1) in.fail("no stage-2 state");
    const std::uint32_t nx = in.get<std::uint32_t>("the grid size"), ny = in.get<std::uint32_t>("the grid size"),
                        nz = in.get<std::uint32_t>("the grid size");
    if (!(Dims{int(nx), int(ny), int(nz)} == d)) in.fail("a stage-2 state of another grid");
    c.iteration = in.get<std::int32_t>("the iteration");
    Stage2Result& r = c.result;
    r = Stage2Result{};
    r.iterations = in.get<std::int32_t>("the iteration count");
    if (c.iteration < 1 || r.iterations != c.iteration) in.fail("an iteration count out of range");
    r.breakthroughIteration = getOptional(in, "the breakthrough iteration");
    const std::uint64_t sources = in.get<std::uint64_t>("the source count");
    if (sources != dom.sourceVoxels.size()) in.fail("a stage-2 state of another number of sources");
    for (std::uint64_t s = 0; s < sources; ++s) r.sourceConnectedIteration.push_back(getOptional(in, "an event"));
    for (double* x : {&r.waterBalanceRelError, &r.totalInjected, &r.totalDrained, &r.pressureCap, &r.seconds,
                      &r.pressureSeconds, &r.transportSeconds, &r.erosionSeconds, &r.workedVoxelIterations})
        *x = in.get<double>("the totals");
    in.getVector(r.sourceInjected, "the water of each source", std::size_t(sources));
    const std::uint64_t rows = in.get<std::uint64_t>("the history");
    if (rows != std::uint64_t(c.iteration)) in.fail("a history of another length than the iterations");
    for (std::uint64_t k = 0; k < rows; ++k) {
        Stage2Record h;
        h.iteration = in.get<std::int32_t>("the history");
        for (double* x : {&h.injected, &h.drained, &h.stored, &h.flow, &h.eroded, &h.balanceError})
            *x = in.get<double>("the history");
        h.channelVoxels = long(in.get<std::int64_t>("the history"));
        h.pressureUpdates = long(in.get<std::int64_t>("the history"));
        h.sourcesConnected = in.get<std::int32_t>("the history");
        r.history.push_back(h);
    }
    c.phase = Stage2PhaseRecord{};
    if (magic == kCarryMagic) {  // the layout before it had no phases
        const std::uint64_t phases = in.get<std::uint64_t>("the phase records");
        if (phases > std::uint64_t(c.iteration)) in.fail("more phases than iterations");
        for (std::uint64_t k = 0; k < phases; ++k) r.phases.push_back(getPhase(in, dom, c.iteration));
        c.phase = getPhase(in, dom, c.iteration);
    }
    const std::uint64_t refills = in.get<std::uint64_t>("the refill levels");
    if (refills > d.count()) in.fail("more refill levels than voxels");
    c.refill.clear();
    for (std::uint64_t k = 0; k < refills; ++k) {
        Refill f;
        f.voxel = std::size_t(in.get<std::uint64_t>("the refill levels"));
        f.level = in.get<double>("the refill levels");
        f.source = in.get<std::int32_t>("the refill levels");
        f.head = in.get<double>("the refill levels");
        if (f.voxel >= d.count() || f.source < 0 || std::uint64_t(f.source) >= sources)
            in.fail("a refill level of a voxel or source that does not exist");
        c.refill.push_back(f);
    }
    c.stored = in.get<double>("the stored water");
    getGrid(in, c.rate, d, "the pressure rates");
    for (float x : c.rate.data)
        if (!(x > 0) || !std::isfinite(x)) in.fail("a pressure rate that is not a finite number > 0");
    c.pressure.restore(in, d);
    c.state = Stage2State(d);
    restoreState(in, c.state);
    getGrid(in, dom.porosity, d, "the porosity");
    for (float x : dom.porosity.data)
        if (!(x >= 0 && x <= 1)) in.fail("a porosity outside [0, 1]");
    getGrid(in, dom.flags, d, "the flags");
    getGrid(in, dom.flow, d, "the flow");
    getGrid(in, dom.water, d, "the water");
    getGrid(in, dom.pressure, d, "the pressure");
    if (in.left() != 0) in.fail("bytes after the stage-2 state");
}

}  // namespace cavesim::stage2
