#include "sim/parameters.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "core/text.h"

namespace cavesim {
namespace {

constexpr std::int64_t kInt64Max = std::numeric_limits<std::int64_t>::max();

/// A `Param` with setters for the optional fields, so an entry reads as one expression.
struct P : Param {
    P&& unitIs(std::string u) && {
        unit = std::move(u);
        return std::move(*this);
    }
    P&& rangeShown(std::string t) && {
        rangeText = std::move(t);
        return std::move(*this);
    }
    P&& defaultShown(std::string t) && {
        defaultText = std::move(t);
        return std::move(*this);
    }
    P&& isRequired(std::string ex) && {
        required = true;
        example = std::move(ex);
        return std::move(*this);
    }
    P&& isNonZero() && {
        nonZero = true;
        return std::move(*this);
    }
    P&& items(std::size_t lo, std::size_t hi) && {
        minItems = lo;
        maxItems = hi;
        return std::move(*this);
    }
    P&& shape(std::string t) && {
        shapeText = std::move(t);
        return std::move(*this);
    }
    P&& appliesWhen(std::function<bool(const void*)> f, std::string reason) && {
        applies = std::move(f);
        notApplicable = std::move(reason);
        return std::move(*this);
    }
};

ParamRange rng(double lo, double hi, const char* ends = "[]", bool domainScaled = false) {
    return ParamRange{lo, hi, ends[0] == '(', ends[1] == ')', domainScaled};
}

template <typename R, typename T>
P base(const char* key, T R::*m, ParamType type, const char* description) {
    P p;
    p.key = key;
    p.type = type;
    p.description = description;
    p.address = [m](const void* r) -> const void* { return &(static_cast<const R*>(r)->*m); };
    return p;
}

template <typename R>
P boolean(const char* key, bool R::*m, const char* description) {
    P p = base(key, m, ParamType::kBool, description);
    p.get = [m](const void* r) { return ParamValue(static_cast<const R*>(r)->*m); };
    p.set = [m](void* r, const ParamValue& v) { static_cast<R*>(r)->*m = std::get<bool>(v); };
    return p;
}

template <typename R, typename I>
P integer(const char* key, I R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kInt, description);
    p.range = range;
    p.get = [m](const void* r) { return ParamValue(static_cast<std::int64_t>(static_cast<const R*>(r)->*m)); };
    p.set = [m](void* r, const ParamValue& v) { static_cast<R*>(r)->*m = static_cast<I>(std::get<std::int64_t>(v)); };
    return p;
}

template <typename R>
P real(const char* key, double R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kReal, description);
    p.range = range;
    p.get = [m](const void* r) { return ParamValue(static_cast<const R*>(r)->*m); };
    p.set = [m](void* r, const ParamValue& v) { static_cast<R*>(r)->*m = std::get<double>(v); };
    return p;
}

template <typename R, typename E>
P choice(const char* key, E R::*m, std::vector<ParamChoice> names, const char* description) {
    P p = base(key, m, ParamType::kChoice, description);
    p.choices = names;
    p.get = [m, names](const void* r) {
        for (const auto& c : names)
            if (c.value == int(static_cast<const R*>(r)->*m)) return ParamValue(std::string(c.name));
        throw RuntimeError("parameter registry: an enum value without a name");
    };
    p.set = [m, names](void* r, const ParamValue& v) {
        for (const auto& c : names)
            if (std::get<std::string>(v) == c.name) static_cast<R*>(r)->*m = static_cast<E>(c.value);
    };
    return p;
}

template <typename R, typename E>
P choiceList(const char* key, std::vector<E> R::*m, std::vector<ParamChoice> names, const char* what,
             const char* description) {
    P p = base(key, m, ParamType::kChoiceList, description);
    p.choices = names;
    std::string list;
    for (const auto& c : names) list += (list.empty() ? "\"" : ", \"") + std::string(c.name) + "\"";
    p.shapeText = std::string("an array of distinct ") + what + " out of " + list + " (may be empty)";
    p.get = [m, names](const void* r) {
        std::vector<std::string> out;
        for (const E e : static_cast<const R*>(r)->*m)
            for (const auto& c : names)
                if (c.value == int(e)) out.push_back(c.name);
        return ParamValue(out);
    };
    p.set = [m, names](void* r, const ParamValue& v) {
        auto& out = static_cast<R*>(r)->*m;
        out.clear();
        for (const auto& s : std::get<std::vector<std::string>>(v))
            for (const auto& c : names)
                if (s == c.name) out.push_back(static_cast<E>(c.value));
    };
    return p;
}

template <typename R>
P int3(const char* key, std::array<int, 3> R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kInt3, description);
    p.range = range;
    p.get = [m](const void* r) {
        const auto& a = static_cast<const R*>(r)->*m;
        return ParamValue(std::vector<std::int64_t>{a[0], a[1], a[2]});
    };
    p.set = [m](void* r, const ParamValue& v) {
        const auto& a = std::get<std::vector<std::int64_t>>(v);
        for (int c = 0; c < 3; ++c) (static_cast<R*>(r)->*m)[c] = int(a[c]);
    };
    return p;
}

template <typename R>
P real3(const char* key, Vec3d R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kReal3, description);
    p.range = range;
    p.shapeText = "an array of 3 numbers";
    p.get = [m](const void* r) {
        const auto& a = static_cast<const R*>(r)->*m;
        return ParamValue(std::vector<double>{a[0], a[1], a[2]});
    };
    p.set = [m](void* r, const ParamValue& v) {
        const auto& a = std::get<std::vector<double>>(v);
        for (int c = 0; c < 3; ++c) (static_cast<R*>(r)->*m)[c] = a[c];
    };
    return p;
}

template <typename R>
P real3List(const char* key, std::vector<Vec3d> R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kReal3List, description);
    p.range = range;
    p.get = [m](const void* r) { return ParamValue(static_cast<const R*>(r)->*m); };
    p.set = [m](void* r, const ParamValue& v) { static_cast<R*>(r)->*m = std::get<std::vector<Vec3d>>(v); };
    return p;
}

template <typename R>
P intList(const char* key, std::vector<int> R::*m, ParamRange range, const char* description) {
    P p = base(key, m, ParamType::kIntList, description);
    p.range = range;
    p.get = [m](const void* r) {
        const auto& a = static_cast<const R*>(r)->*m;
        return ParamValue(std::vector<std::int64_t>(a.begin(), a.end()));
    };
    p.set = [m](void* r, const ParamValue& v) {
        const auto& a = std::get<std::vector<std::int64_t>>(v);
        static_cast<R*>(r)->*m = std::vector<int>(a.begin(), a.end());
    };
    return p;
}

/// `at` (one voxel) or `box` (two corners) of a terminal: the value is empty when the record's
/// box is written the other way.
template <typename R>
P voxelBox(const char* key, VoxelBox R::*m, bool corners, const char* description) {
    P p = base(key, m, corners ? ParamType::kVoxelBox : ParamType::kVoxel, description);
    p.range = rng(-(1 << 20), 1 << 20);
    p.get = [m, corners](const void* r) {
        const VoxelBox& b = static_cast<const R*>(r)->*m;
        std::vector<std::int64_t> v;
        if ((b.lo == b.hi) != corners) {
            v.assign(b.lo.begin(), b.lo.end());
            if (corners) v.insert(v.end(), b.hi.begin(), b.hi.end());
        }
        return ParamValue(v);
    };
    p.set = [m, corners](void* r, const ParamValue& v) {
        const auto& a = std::get<std::vector<std::int64_t>>(v);
        VoxelBox& b = static_cast<R*>(r)->*m;
        for (int c = 0; c < 3; ++c) {
            b.lo[c] = int(a[c]);
            b.hi[c] = int(a[corners ? c + 3 : c]);
        }
    };
    return p;
}

/// A file path; "" means none.
template <typename R>
P path(const char* key, std::string R::*m, const char* description) {
    P p = base(key, m, ParamType::kPath, description);
    p.shapeText = "a file path of at most 4096 characters (relative to the scenario file's folder), or \"\" for none";
    p.rangeText = "a path, or `\"\"`";
    p.get = [m](const void* r) { return ParamValue(static_cast<const R*>(r)->*m); };
    p.set = [m](void* r, const ParamValue& v) { static_cast<R*>(r)->*m = std::get<std::string>(v); };
    return p;
}

/// A plain table whose record is `R` inside the scenario.
template <typename R>
ParamSection table(const char* path, R* (*of)(Scenario&), const char* heading, std::vector<P> params) {
    ParamSection s;
    s.path = path;
    s.heading = heading;
    s.params.assign(params.begin(), params.end());
    s.count = [](const Scenario&) -> std::size_t { return 1; };
    s.record = [of](const Scenario& sc, std::size_t) -> const void* { return of(const_cast<Scenario&>(sc)); };
    s.mutableRecord = [of](Scenario& sc, std::size_t) -> void* { return of(sc); };
    s.defaults = [of]() -> const void* {
        static const Scenario d;
        return of(const_cast<Scenario&>(d));
    };
    return s;
}

/// A table of arrays whose records are the elements of `v` in the scenario.
template <typename R>
ParamSection tableArray(const char* path, std::vector<R> Scenario::*v, std::size_t maxEntries, const char* heading,
                        std::vector<P> params) {
    ParamSection s;
    s.path = path;
    s.isArray = true;
    s.maxEntries = maxEntries;
    s.heading = heading;
    s.params.assign(params.begin(), params.end());
    s.count = [v](const Scenario& sc) { return (sc.*v).size(); };
    s.record = [v](const Scenario& sc, std::size_t i) -> const void* { return &(sc.*v)[i]; };
    s.mutableRecord = [v](Scenario& sc, std::size_t i) -> void* { return &(sc.*v)[i]; };
    s.append = [v](Scenario& sc) -> void* { return &(sc.*v).emplace_back(); };
    s.defaults = []() -> const void* {
        static const R d{};
        return &d;
    };
    return s;
}

/// A table of arrays whose records are the elements of the vector `of` returns (one inside a stage's options).
template <typename R>
ParamSection tableArrayOf(const char* path, std::vector<R>* (*of)(Scenario&), std::size_t maxEntries,
                          const char* heading, std::vector<P> params) {
    ParamSection s;
    s.path = path;
    s.isArray = true;
    s.maxEntries = maxEntries;
    s.heading = heading;
    s.params.assign(params.begin(), params.end());
    s.count = [of](const Scenario& sc) { return of(const_cast<Scenario&>(sc))->size(); };
    s.record = [of](const Scenario& sc, std::size_t i) -> const void* { return &(*of(const_cast<Scenario&>(sc)))[i]; };
    s.mutableRecord = [of](Scenario& sc, std::size_t i) -> void* { return &(*of(sc))[i]; };
    s.append = [of](Scenario& sc) -> void* { return &of(sc)->emplace_back(); };
    s.defaults = []() -> const void* {
        static const R d{};
        return &d;
    };
    return s;
}

Scenario* top(Scenario& s) {
    return &s;
}
Scenario* domain(Scenario& s) {
    return &s;
}
Scenario* rock(Scenario& s) {
    return &s;
}
NoiseSettings* noise(Scenario& s) {
    return &s.noise;
}
Stage1Options* stage1(Scenario& s) {
    return &s.stage1;
}
Stage2Options* stage2(Scenario& s) {
    return &s.stage2;
}
Hydrology* hydrology(Scenario& s) {
    return &s.stage2.hydrology;
}
std::vector<Stage2Phase>* phases(Scenario& s) {
    return &s.stage2.phases;
}
OutputOptions* output(Scenario& s) {
    return &s.output;
}
SiteSettings* site(Scenario& s) {
    return &s.site;
}
SpeleothemOptions* speleothems(Scenario& s) {
    return &s.speleothems;
}

/// The fields of a slab of raised porosity around a plane ([[rock.plane]], [[rock.inception_horizon]]);
/// `what` names the plane in the descriptions of `point` and `thickness`.
std::vector<P> planeSlabParams(const std::string& what, const char* normalDoc, const char* porosityDoc) {
    return {
        real3("point", &PlaneFeature::point, rng(-1, 1, "[]", true), ("a point on the " + what).c_str())
            .unitIs("voxels")
            .isRequired("[30.0, 30.0, 10.0]"),
        real3("normal", &PlaneFeature::normal, rng(-1e6, 1e6), normalDoc)
            .rangeShown("each [-10⁶, 10⁶], non-zero")
            .isNonZero(),
        real("thickness", &PlaneFeature::thickness, rng(0, 1e6, "(]"), ("slab thickness across the " + what).c_str())
            .unitIs("voxels"),
        real("porosity", &PlaneFeature::porosity, rng(0, 1), porosityDoc),
        real("extent", &PlaneFeature::extent, rng(0, 1e6), "in-plane radius around `point`; 0 = unbounded")
            .unitIs("voxels"),
    };
}

std::vector<ParamSection> makeRegistry() {
    using PM = ProtosinkMode;
    using ZS = ZoneSpeed;
    using GF = GridFace;
    using TW = TransportWeight;
    using FB = FlowBlending;
    using MS = MeshStyle;
    using CE = CaveExtent;
    using EF = ExportFormat;
    using MN = MeshNormals;
    using RR = RateRule;
    using SI = SourceInflow;
    using PK = PlaneKind;
    using RK = RechargeKind;
    std::vector<ParamSection> r;

    ParamSection& topLevel = r.emplace_back(table<Scenario>(
        "", top, "Top level",
        {
            P(base("name", &Scenario::name, ParamType::kString, "names the default output folder `out/<name>`"))
                .shape("a string of 1-64 letters, digits, '-' or '_'")
                .rangeShown("1–64 characters of `A–Z a–z 0–9 _ -`"),
            integer("seed", &Scenario::seed, rng(0, double(kInt64Max)),
                    "seeds the rock noise and every random choice (stage-1 protosink clusters)")
                .rangeShown("0 – 2⁶³−1"),
        }));
    {
        Param& name = topLevel.params[0];
        name.get = [](const void* s) { return ParamValue(static_cast<const Scenario*>(s)->name); };
        name.set = [](void* s, const ParamValue& v) { static_cast<Scenario*>(s)->name = std::get<std::string>(v); };
    }
    topLevel.prose =
        "A scenario is a TOML file. Every key is optional unless marked *required*; every key has a\n"
        "default, a unit and an allowed range, listed here. Positions and sizes in `[domain]`, `[rock]`,\n"
        "`[[source]]` and `[[sink]]` are in **voxel (index) units**: voxel `(i, j, k)` has its centre at\n"
        "`((i, j, k) + 0.5) · voxel_size` metres in the output files. `z` is up. A domain with `ny = 1` is a\n"
        "2D vertical section.\n\n"
        "The parser is strict: an unknown or misspelt key, a wrong type, an out-of-range value, a source or\n"
        "sink outside the domain, a source overlapping a sink, a stage 2 without a sink, or malformed TOML\n"
        "gives one message naming the file, the line, the key, the value and what is allowed, and exit code\n"
        "2; no output is written. `cavesim validate FILE` checks a file without running it. A run writes\n"
        "the *effective* scenario (every default filled in) to `DIR/scenario.toml`; that file is itself a\n"
        "valid scenario and reproduces the run (its last line, a comment, records the `state.cavesim` the\n"
        "run wrote, for `cavesim report`). A scenario is a regular file of at most 16 MiB whose dotted keys\n"
        "and table names have at most 32 parts, with non-ASCII characters only inside strings and comments.\n\n"
        "These key names are a contract: keys may be added, never renamed or repurposed.\n\n"
        "`cavesim reference` prints this reference (this file is its output); `cavesim reference --example`\n"
        "prints a complete scenario with every key at its default, commented.";

    r.push_back(table<Scenario>(
        "domain", domain, "",
        {
            int3("size", &Scenario::size, rng(1, 1024), "`nx, ny, nz`")
                .unitIs("voxels")
                .rangeShown("each 1–1024; the run's memory is estimated and checked before it starts"),
            real("voxel_size", &Scenario::voxelSize, rng(1e-3, 1e4), "edge of one voxel; scales every output length")
                .unitIs("m"),
        }));

    r.push_back(table<Scenario>(
        "rock", rock, "",
        {
            real("porosity", &Scenario::rockPorosity, rng(0, 1), "background porosity R (water capacity of a voxel)"),
        }));

    ParamSection& noiseSec = r.emplace_back(table<NoiseSettings>(
        "rock.noise", noise, "gradient noise",
        {
            real("amplitude", &NoiseSettings::amplitude, rng(0, 1),
                 "gradient-noise porosity variation, ± this (clamped to [0, 1])"),
            real("scale", &NoiseSettings::scale, rng(0.01, 1e6), "feature size of the noise").unitIs("voxels"),
            integer("octaves", &NoiseSettings::octaves, rng(1, 8), "fractal octaves, each half the size and amplitude"),
        }));
    noiseSec.notes =
        "Write the noise as an inline table, `noise = { amplitude = 0.02, scale = 8.0 }`, or as `[rock.noise]`.";

    ParamSection& sphere = r.emplace_back(
        tableArray("rock.sphere", &Scenario::spheres, 4096, "obstacles",
                   {
                       real3("center", &SphereObstacle::center, rng(-1, 1, "[]", true), "centre")
                           .unitIs("voxels")
                           .isRequired("[30.0, 30.0, 10.0]"),
                       real("radius", &SphereObstacle::radius, rng(0, 1e6, "(]"), "radius").unitIs("voxels"),
                       real("core_porosity", &SphereObstacle::corePorosity, rng(0, 1),
                            "porosity at the centre; it rises quadratically to the rock value at the rim"),
                   }));
    sphere.prose = "At most 4096 spheres.";

    std::vector<P> planeParams = planeSlabParams("plane", "plane normal (need not be unit length)",
                                                 "porosity inside the slab (the larger of this and the rock's)");
    planeParams.push_back(choice("kind", &PlaneFeature::kind,
                                 {{"bedding", int(PK::kBedding)}, {"fracture", int(PK::kFracture)}},
                                 "both set the fracture flag; the name is kept in the report"));
    ParamSection& plane = r.emplace_back(
        tableArray("rock.plane", &Scenario::planes, 1024, "bedding planes and fractures", std::move(planeParams)));
    plane.prose = "A slab of raised porosity around a plane of any orientation. At most 1024 planes.";

    ParamSection& channel = r.emplace_back(tableArray(
        "rock.channel", &Scenario::channels, 1024, "known conduits and synthetic protochannels",
        {
            real3List("points", &ChannelFeature::points, rng(-1, 1, "[]", true), "polyline")
                .unitIs("voxels")
                .isRequired("[[10.0, 30.0, 10.0], [50.0, 30.0, 10.0]]")
                .items(2, 0)
                .shape("an array of at least 2 points [x, y, z]")
                .rangeShown("≥ 2 points, within ±4 × the largest domain size"),
            real("radius", &ChannelFeature::radius, rng(0, 1e6),
                 "voxels whose centre lies within this distance are inside (at least the voxels the line passes "
                 "through)")
                .unitIs("voxels"),
            real("porosity", &ChannelFeature::porosity, rng(0, 1), "porosity inside"),
            boolean("protochannel", &ChannelFeature::protochannel,
                    "flag the voxels as protochannel, so stage 2 treats them as channel for the pressure rule "
                    "(stage-2-only runs, paper Figures 8 and 9)"),
        }));
    channel.prose = "At most 1024 channels with at most 65 536 points together.";

    ParamSection& inception = r.emplace_back(tableArray(
        "rock.inception_horizon", &Scenario::inceptionHorizons, 64, "inception horizons: bedding planes of early flow",
        planeSlabParams("horizon", "normal of the horizon (need not be unit length)",
                        "porosity inside the slab (the larger of this and the rock's): stage-1 capacity and zone "
                        "speed follow it")));
    inception.prose =
        "A bedding plane that is an inception horizon (Lowe 1992; KarstNSim): a slab like `[[rock.plane]]`\n"
        "whose voxels also carry early flow in stage 2. Stage 1 sees its porosity (a higher edge capacity and\n"
        "a faster zone front); in stage 2 the pressure rate of a horizon voxel that is not yet channel is read\n"
        "from its porosity against the rock's, by the rule stage-1 protochannels follow with the rock's\n"
        "porosity in place of the voxel's initial one (docs/geology.md). At most 64.";

    ParamSection& family = r.emplace_back(tableArray(
        "rock.fracture_family", &Scenario::fractureFamilies, 16, "fracture families: a discrete fracture network",
        {
            real("dip_direction", &FractureFamily::dipDirection, rng(0, 360, "[)"),
                 "azimuth of the mean plane's dip, clockwise from north (+y; +x is east)")
                .unitIs("degrees"),
            real("dip", &FractureFamily::dip, rng(0, 90), "mean plane's dip below the horizontal").unitIs("degrees"),
            real("kappa", &FractureFamily::kappa, rng(0, 1e6, "(]"),
                 "Fisher concentration of the poles about the mean pole (larger = tighter; 20 ≈ 18° spread)"),
            real("spacing", &FractureFamily::spacing, rng(0, 1e6),
                 "mean spacing along the mean pole: P32 = 1 / spacing; 0 = give `density`")
                .unitIs("voxels"),
            real("density", &FractureFamily::density, rng(0, 1), "fractures per unit volume (P30); 0 = give `spacing`")
                .unitIs("1/voxel³"),
            real("length_exponent", &FractureFamily::lengthExponent, rng(0, 10, "(]"),
                 "a of the power-law density of disc diameters, p(l) ∝ l^−a on [min_length, max_length]"),
            real("min_length", &FractureFamily::minLength, rng(0, 1e6, "(]"), "least disc diameter").unitIs("voxels"),
            real("max_length", &FractureFamily::maxLength, rng(0, 1e6, "(]"), "largest disc diameter").unitIs("voxels"),
            real("aperture", &FractureFamily::aperture, rng(0, 1e6, "(]"), "slab thickness across each disc")
                .unitIs("voxels"),
            real("porosity", &FractureFamily::porosity, rng(0, 1),
                 "porosity inside the slab (the larger of this and the rock's)"),
        }));
    family.prose =
        "Discs drawn from `seed` (each family its own random stream): centres uniform in the block grown by\n"
        "max_length / 2 on every side (volume V), poles from a Fisher distribution about the mean pole,\n"
        "diameters from a truncated power law; the discs that reach the block are kept. round(V / (spacing ·\n"
        "E[disc area])) or round(density · V) centres are drawn, so P32 inside the block is 1 / spacing\n"
        "whatever the discs' size. A family that cannot\n"
        "fit — min_length above max_length or above the block's longest side, a spacing above it, no disc\n"
        "at all, more than 10⁶ discs, both or neither of spacing and density — is an error. At most 16.\n"
        "report.json `fracture_network` gives each family's count, measured mean orientation, estimated\n"
        "kappa and P32; `images/fractures.png` draws the traces (docs/geology.md).";
    family.setLine = [](void* r, int line) { static_cast<FractureFamily*>(r)->line = line; };

    ParamSection& source = r.emplace_back(tableArray(
        "source", &Scenario::sources, 256, "",
        {
            voxelBox("at", &SourceSpec::box, false, "one voxel (give `at` or `box`)")
                .unitIs("voxels")
                .isRequired("[30, 30, 19]")
                .defaultShown("*required* (or `box`)")
                .rangeShown("inside the domain"),
            voxelBox("box", &SourceSpec::box, true, "inclusive voxel indices of a box (give `at` or `box`)")
                .unitIs("voxels")
                .rangeShown("inside the domain, x0 ≤ x1, y0 ≤ y1, z0 ≤ z1"),
            real("pressure", &SourceSpec::pressure, rng(0, 1e6, "(]"),
                 "stage 1: zone front speed; stage 2: pressure cap and refill level (relative to the strongest source)")
                .unitIs("relative"),
        }));
    source.prose =
        "Give either `at = [x, y, z]` (one voxel) or `box = [[x0, y0, z0], [x1, y1, z1]]` (inclusive voxel\n"
        "indices). Every source and sink must lie inside the domain; a source may not overlap a sink.";
    source.notes =
        "At least one source is required when a stage is enabled; stage 2 requires at least one sink.\n"
        "At most 256 `[[source]]` and 256 `[[sink]]` entries (each may be a box of many voxels): stage 1\n"
        "divides the block into one zone per source and solves a flow network in each.";
    source.params[0].required = false;  // `at` or `box`: the parser checks that one is given
    source.limitReason = "one [[source]] may be a box of many voxels";
    source.setLine = [](void* r, int line) { static_cast<SourceSpec*>(r)->line = line; };

    ParamSection& sink = r.emplace_back(
        tableArray("sink", &Scenario::sinks, 256, "",
                   {
                       voxelBox("at", &SinkSpec::box, false, "one voxel (give `at` or `box`)")
                           .unitIs("voxels")
                           .isRequired("[30, 30, 0]")
                           .defaultShown("*required* (or `box`)")
                           .rangeShown("inside the domain"),
                       voxelBox("box", &SinkSpec::box, true, "inclusive voxel indices of a box (give `at` or `box`)")
                           .unitIs("voxels")
                           .rangeShown("inside the domain, x0 ≤ x1, y0 ≤ y1, z0 ≤ z1"),
                   }));
    sink.params[0].required = false;
    sink.limitReason = "one [[sink]] may be a box of many voxels";
    sink.setLine = [](void* r, int line) { static_cast<SinkSpec*>(r)->line = line; };

    const auto isSinkholes = [](const void* rec) {
        return static_cast<const RechargeSpec*>(rec)->kind == RK::kSinkholes;
    };
    ParamSection& recharge = r.emplace_back(tableArray(
        "recharge", &Scenario::recharge, 64, "sinkholes, diffuse recharge, sinking streams",
        {
            choice("kind", &RechargeSpec::kind,
                   {{"sinkholes", int(RK::kSinkholes)}, {"diffuse", int(RK::kDiffuse)}, {"stream", int(RK::kStream)}},
                   "`count` sinkholes drawn from `seed` in `area`; a diffuse input per `spacing` cell of `area`; "
                   "inputs every `spacing` voxels along `points`"),
            intList("area", &RechargeSpec::area, rng(0, 1023),
                    "sinkholes, diffuse: `[x0, y0, x1, y1]`, inclusive voxel columns of the top face; `[]` = all")
                .unitIs("voxels")
                .items(0, 4)
                .shape("[] or [x0, y0, x1, y1]")
                .rangeShown("[] or 4 column indices inside the top face, x0 ≤ x1, y0 ≤ y1"),
            integer("count", &RechargeSpec::count, rng(1, 256), "sinkholes: how many")
                .appliesWhen(isSinkholes, "only sinkholes take a count; leave it out for this kind"),
            integer("radius", &RechargeSpec::radius, rng(0, 64),
                    "sinkholes: each is a (2r+1)² × (r+1) box under the land surface (2r+1 at most the area's sides, "
                    "r+1 at most the layers of rock under the land: nz, or fewer under a `[site] dem`), at least "
                    "2r+1 apart")
                .unitIs("voxels")
                .appliesWhen(isSinkholes, "only sinkholes take a radius; leave it out for this kind"),
            real("spacing", &RechargeSpec::spacing, rng(1, 1024), "diffuse: cell size; stream: input spacing")
                .unitIs("voxels"),
            real("pressure", &RechargeSpec::pressure, rng(0, 1e6, "(]"),
                 "sinkholes: each one's `[[source]] pressure`; diffuse, stream: the total, shared equally")
                .unitIs("relative"),
            real3List("points", &RechargeSpec::points, rng(-1, 1, "[]", true),
                      "stream: the polyline, inside the block (z = nz − 1 is the top face; under a `[site] dem` an "
                      "input above the land is lowered onto it)")
                .unitIs("voxels")
                .items(0, 1024)
                .shape("an array of points [x, y, z]")
                .rangeShown("stream: 2–1024 points inside the block; otherwise `[]`"),
        }));
    recharge.prose =
        "Recharge expands into ordinary sources on the land surface — the block's top layer, or with a\n"
        "`[site] dem` the highest rock voxel of each column — after the `[[source]]` entries and before a\n"
        "site's sinkholes; everything downstream sees sources. Together with the `[[source]]` entries and a\n"
        "site's sinkholes at most 256 sources. Recharge outside the top face's columns, on a column the DEM\n"
        "leaves all air, sinkholes that do not fit in their area (or under the DEM in the block's layers),\n"
        "an input below `[site] base_of_limestone`, or an input on a sink or a spring is an\n"
        "error (docs/geology.md). A key of another kind is an error too: `count` or `radius` on a stream or\n"
        "diffuse entry, `points` on sinkholes or diffuse, `area` on a stream.";
    recharge.setLine = [](void* r, int line) { static_cast<RechargeSpec*>(r)->line = line; };

    const std::vector<ParamChoice> faces{{"-x", int(GF::kMinusX)}, {"+x", int(GF::kPlusX)},  {"-y", int(GF::kMinusY)},
                                         {"+y", int(GF::kPlusY)},  {"-z", int(GF::kMinusZ)}, {"+z", int(GF::kPlusZ)}};
    ParamSection& s1 = r.emplace_back(table<Stage1Options>(
        "stage1", stage1, "protochannels (paper §3.1)",
        {
            boolean("enabled", &Stage1Options::enabled, "run stage 1"),
            choice("protosinks", &Stage1Options::protosinks,
                   {{"boundary", int(PM::kBoundary)}, {"clustered", int(PM::kClustered)}},
                   "every zone-boundary voxel drains (isotropic growth), or `clusters` clusters (growth in preferred "
                   "directions)"),
            integer("clusters", &Stage1Options::clusters, rng(1, 64),
                    "number of protosink clusters per zone when clustered; centres drawn from `seed`, spread out (best "
                    "of 16 random draws each)"),
            real("cluster_radius", &Stage1Options::clusterRadius, rng(0, 1e6),
                 "radius of one protosink cluster: the boundary voxels within this distance of its centre")
                .unitIs("voxels"),
            real3List("aim", &Stage1Options::aim, rng(-1, 1, "[]", true),
                      "optional: one cluster per point, centred on the zone's boundary voxel nearest to it (`clusters` "
                      "is then not used)")
                .unitIs("voxels")
                .items(0, 1024)
                .shape("an array of points [x, y, z]")
                .rangeShown("at most 1024 points, within ±4 × the largest domain size"),
            choice("permeability", &Stage1Options::permeability,
                   {{"uniform", int(ZS::kUniform)}, {"porosity", int(ZS::kPorosity)}},
                   "zone front speed: the source's pressure, or pressure × R / R̄ (local porosity over the block's "
                   "mean; rock of porosity 0 is never entered)"),
            real("protochannel_porosity", &Stage1Options::protochannelPorosity, rng(0, 1),
                 "porosity shown along protochannels after stage 1 (display erosion, never lowered; reset by the "
                 "interim step)"),
            real("capacity_exponent", &Stage1Options::capacityExponent, rng(0, 8, "(]"),
                 "flow-network edge capacity = (smaller porosity of the two voxels)^exponent / edge length (1, √2 or "
                 "√3: the 26 neighbours); its resistance is 1 / capacity"),
            integer("max_graph_voxels", &Stage1Options::maxGraphVoxels, rng(1, 1e9),
                    "a zone whose flow network would be larger (the zone, or its `network_voxels` nearest voxels) is "
                    "refused with an error before any network is built")
                .unitIs("voxels"),
            integer("network_voxels", &Stage1Options::networkVoxels, rng(1, 1e9),
                    "a larger zone's flow network is limited to the neighbourhood of its source: the zone's this many "
                    "voxels its front reached first (an iso-arrival-time ball around the source; its edge drains like "
                    "the zone's boundary). Bounds stage 1's memory (about 1,450 bytes per network voxel) and time")
                .unitIs("voxels"),
            choiceList("boundary_faces", &Stage1Options::boundaryFaces, faces, "grid faces",
                       "faces of the block that count as zone boundary (protosinks there), besides the boundaries "
                       "between zones. The default leaves out the top, the recharge side the sources are fed from. The "
                       "±y faces of a 2D section (`ny = 1`) never count")
                .rangeShown(
                    "distinct values out of `\"-x\"`, `\"+x\"`, `\"-y\"`, `\"+y\"`, `\"-z\"`, `\"+z\"`; may be empty"),
            real("protosink_share", &Stage1Options::protosinkShare, rng(0, 1, "(]"),
                 "the protosinks of a zone drain together this fraction of what the source's links can carry, each in "
                 "proportion to its porosity; below 1 every protosink the rock can reach is fed, so growth is "
                 "isotropic"),
            real("branch_flow", &Stage1Options::branchFlow, rng(0, 1),
                 "a voxel becomes protochannel only if at least this fraction of its zone's flow passes through it: "
                 "smaller values give more, longer branches reaching closer to the zone boundary; 0 marks every traced "
                 "path"),
            real("resistance_noise", &Stage1Options::resistanceNoise, rng(0, 1),
                 "random variation of link resistance (sub-voxel heterogeneity, from `seed`): a factor e^(2·noise·(2u "
                 "− 1)), u uniform in [0, 1), so 0.5 gives factors between 1/e and e. Lattice paths in directions "
                 "between the 26 link directions tie; without enough noise the least-resistance routes gather along "
                 "the link directions and the protochannels follow the grid. 0 = none"),
            integer("sink_gap", &Stage1Options::sinkGap, rng(1, 64),
                    "rock kept between protochannels and sinks: voxels within this distance of a sink voxel (along "
                    "any of the 26 neighbour directions: the largest of |dx|, |dy|, |dz|) are left out of the flow "
                    "networks, so stage 2 starts with every source cut off from the sinks; an `aim` point within it is "
                    "refused")
                .unitIs("voxels"),
        }));
    s1.prose =
        "Stage 1 divides the block into pressure zones (one per source, by fast marching), solves a flow\n"
        "network in every zone and traces protochannels from the zone boundary back to the source; the\n"
        "model and every rule are described in `src/sim/stage1.h` and `src/flownet/*.h`.";

    r.push_back(table<Stage2Options>(
        "stage2", stage2, "growth and linkage (paper §3.2)",
        {
            boolean("enabled", &Stage2Options::enabled, "run the interim step and stage 2"),
            integer("iterations", &Stage2Options::iterations, rng(0, 1e6),
                    "iterations of pressure → transport → blending → erosion"),
            real("p_rate", &Stage2Options::pRate, rng(0, 1e6, "(]"), "pressure rise per voxel of rock (`P_rate`)")
                .unitIs("pressure / voxel"),
            real("p_rate_channel", &Stage2Options::pRateChannel, rng(0, 1e6, "(]"),
                 "pressure rise per voxel of channel (`P_rate^channel`); at most `p_rate`")
                .unitIs("pressure / voxel"),
            real("w0", &Stage2Options::w0, rng(0, 10), "erosion factor of Eq. 1"),
            real("wa", &Stage2Options::wa, rng(0, 100), "blending factor of Eq. 2"),
            real("m", &Stage2Options::m, rng(0, 4, "(]"), "erosion exponent of Eq. 1"),
            real("pressure_scale", &Stage2Options::pressureScale, rng(0, 1e9),
                 "stage-2 pressure (head) of a source = its `pressure` × this; the strongest head caps the pressure "
                 "front. 0 = automatic: the strongest head is 2 · `p_rate` · (nx + ny + nz), far above anything the "
                 "front reaches, so the cap never flattens the field where channels grow, and the other heads are in "
                 "proportion to their `pressure`")
                .unitIs("pressure")
                .defaultShown("0 (auto)"),
            real(
                "channel_threshold", &Stage2Options::channelThreshold, rng(0, 1, "(]"),
                "an eroded voxel whose porosity reaches this becomes channel (the cave) and takes the channel pressure "
                "rate"),
            real("protochannel_porosity", &Stage2Options::protochannelPorosity, rng(0, 1),
                 "interim step: porosity of protochannel voxels (never lowered below their own)"),
            real(
                "source_porosity", &Stage2Options::sourcePorosity, rng(0, 1, "(]"),
                "capacity of a source voxel = water injected per iteration at most: the discharge, and so how wide the "
                "channels grow (the Figure 10 cave: W = 3.5 m at 0.1, 4.9 m at 0.3, 6.1 m at 1.0)"),
            choice(
                "weight", &Stage2Options::weight,
                {{"proportional", int(TW::kProportional)}, {"uniform", int(TW::kUniform)}},
                "Listing 1's weight(ΔP): shares proportional to the pressure drop per unit distance, or equal shares"),
            choice(
                "blending", &Stage2Options::blending, {{"max", int(FB::kMax)}, {"split", int(FB::kSplit)}},
                "flow blending of Eq. 2: `f_a` of a voxel is the largest `f_c` among its lower-pressure neighbours (a "
                "wall feels the flow of the channel beside it), or the sum of the shares of `f_c` that each lower "
                "neighbour splits equally over its higher-pressure neighbours"),
            choice("rate_rule", &Stage2Options::rateRule,
                   {{"porosity", int(RR::kPorosity)}, {"channel_flag", int(RR::kChannelFlag)}},
                   "pressure rate of a voxel: `porosity` goes from `p_rate` to `p_rate_channel` geometrically as the "
                   "porosity rises from its initial value to `channel_threshold`, in 16 steps, so a protochannel is a "
                   "preferred path that stage 2 still has to open; `channel_flag` is the paper's rule, "
                   "`p_rate_channel` on channel and protochannel voxels from the start (docs/model.md)"),
            choice("inflow", &Stage2Options::inflow, {{"head", int(SI::kHead)}, {"level", int(SI::kLevel)}},
                   "water a source voxel takes in each iteration: `head` refills it to the fraction (head − field "
                   "pressure at the voxel) / the largest head of its porosity, so a stronger source and a channel "
                   "that lowers the pressure at the source both raise the discharge; `level` refills it to "
                   "`pressure` / the largest source pressure whatever the field (docs/model.md)"),
            intList("snapshots", &Stage2Options::snapshots, rng(0, 1e6),
                    "iterations after which a picture of the state is written (`images/iter_NNNN.png`, combined in "
                    "`images/sequence.png`: up to 6 frames a row, at most 8192 pixels wide); each from 1 to the run's "
                    "iterations (with `[[phase]]` entries, theirs together). A snapshot writes nothing else, so it "
                    "is an error with `[output] images = false`")
                .unitIs("iterations")
                .items(0, 32)
                .shape("an array of iteration numbers")
                .rangeShown("at most 32 entries, 0–10⁶ each"),
        }));

    ParamSection& hydro = r.emplace_back(table<Hydrology>(
        "hydrology", hydrology, "water table: vadose and phreatic zones (docs/model.md)",
        {
            real("water_table", &Hydrology::waterTable, rng(-1, 1e6),
                 "height (z, voxel index units) of the water table at the block's centre column; voxels whose "
                 "centre lies above it are vadose (water moves down under gravity), the rest phreatic (the paper's "
                 "pressure model); −1 = no water table. Otherwise at most nz − 1")
                .unitIs("voxels")
                .defaultShown("-1 (none)")
                .rangeShown("-1, or 0 – nz − 1"),
            real("dip", &Hydrology::dip, rng(0, 89), "dip of the water table (0 = level)").unitIs("degrees"),
            real("dip_direction", &Hydrology::dipDirection, rng(0, 360, "[)"),
                 "direction the table falls towards, clockwise from +y")
                .unitIs("degrees"),
            real("vadose_lateral", &Hydrology::lateral, rng(0, 1, "[)"),
                 "fraction of the field pressure added to a vadose voxel's gravitational potential: how strongly "
                 "vadose water drifts towards the sinks along a passage floor (0 = straight down only); below 1, "
                 "so down is always downhill"),
            boolean("from_site", &Hydrology::fromSite,
                    "the water table is the surface of `[site] water_table` (needs it; then leave `water_table`, "
                    "`dip` and `dip_direction` at their defaults); a phase's `water_table` still replaces it by a "
                    "level for that phase"),
        }));
    hydro.omitAtDefaults = true;
    hydro.setLine = [](void* r, int line) { static_cast<Hydrology*>(r)->line = line; };
    hydro.prose =
        "A water table divides the block into a vadose zone above it, where water is not pressurised and\n"
        "moves down under gravity (shafts and canyons), and a phreatic zone below, where the paper's\n"
        "pressure model holds. Without it (the default) stage 2 is the paper's model unchanged. A key the\n"
        "run would ignore is an error: any key away from its default while stage 2 is off, and `dip`,\n"
        "`dip_direction` or `vadose_lateral` away from their defaults when no water table is set (here, by\n"
        "`from_site`, or by a `[[phase]]`).";

    ParamSection& phase = r.emplace_back(tableArrayOf(
        "phase", phases, 64, "base-level phases",
        {
            integer("iterations", &Stage2Phase::iterations, rng(1, 1e6), "stage-2 iterations of this phase")
                .unitIs("iterations")
                .isRequired("100"),
            real("water_table", &Stage2Phase::waterTable, rng(-1, 1e6),
                 "the water table's height at the centre column during this phase (as `[hydrology] water_table`); "
                 "−1 = `[hydrology] water_table`")
                .unitIs("voxels")
                .defaultShown("-1 ([hydrology])")
                .rangeShown("-1, or 0 – nz − 1"),
            intList("sinks", &Stage2Phase::sinks, rng(1, 256),
                    "the sinks that drain during this phase (1-based: the `[[sink]]` entries in file order, then a "
                    "`[site]`'s springs); empty = all")
                .items(0, 256)
                .shape("an array of sink numbers")
                .rangeShown("1 – number of sinks"),
            intList("sources", &Stage2Phase::sources, rng(1, 256),
                    "the sources that inject during this phase (1-based: the `[[source]]` entries in file order, then "
                    "the `[[recharge]]` inputs, then a `[site]`'s sinkholes); empty = all")
                .items(0, 256)
                .shape("an array of source numbers")
                .rangeShown("1 – number of sources"),
        }));
    phase.prose =
        "Base-level phases run in file order in stage 2, each with its own water table and active sinks\n"
        "and sources; when given, their iterations replace `[stage2] iterations`. A falling water table\n"
        "leaves the passages of an earlier phase vadose (or dry) and grows a lower level. At most 64;\n"
        "an error while stage 2 is off.";
    phase.setLine = [](void* r, int line) { static_cast<Stage2Phase*>(r)->line = line; };
    phase.exampleCommented = true;
    phase.nonEmpty = true;
    phase.exampleNote = "optional: phases replace [stage2] iterations; remove the '# '";

    r.push_back(table<OutputOptions>(
        "output", output, "",
        {
            choice("mesh_style", &OutputOptions::meshStyle, {{"smooth", int(MS::kSmooth)}, {"voxel", int(MS::kVoxel)}},
                   "`voxel` also writes the blocky mesh of cave voxels (`cave_voxels.obj`); `cavesim run --mesh-style` "
                   "overrides"),
            integer("image_width", &OutputOptions::imageWidth, rng(256, 8192), "width of the pictures")
                .unitIs("pixels"),
            boolean("images", &OutputOptions::images, "write `images/*.png`"),
            boolean("mesh", &OutputOptions::mesh, "write `cave.obj` and `cave.ply`"),
            choice(
                "cave", &OutputOptions::cave,
                {{"channels", int(CE::kChannels)}, {"with_protochannels", int(CE::kWithProtochannels)}},
                "which voxels are the cave that is meshed, drawn and measured: the stage-2 channels, or the channels "
                "and the stage-1 protochannels as 1-voxel side passages (the paper's Figures 10–12 show both kinds; "
                "`docs/reproduction.md` gives Table 4 both ways). Does not change the simulation"),
            choiceList("formats", &OutputOptions::formats,
                       {{"glb", int(EF::kGlb)},
                        {"vtk", int(EF::kVtk)},
                        {"stl", int(EF::kStl)},
                        {"svx", int(EF::kSvx)},
                        {"th", int(EF::kTh)},
                        {"gocad", int(EF::kGocad)},
                        {"csv", int(EF::kCsv)},
                        {"vdb", int(EF::kVdb)}},
                       "formats",
                       "files for other tools (README, \"Output files\"): `glb` cave.glb, `vtk` state.vti and "
                       "skeleton.vtp, `stl` cave.stl, `svx` cave.svx, `th` cave.th, `gocad` cave.ts and skeleton.pl, "
                       "`csv` history.csv and branches.csv, `vdb` cave.vdb; `cavesim run --formats` overrides. Mesh "
                       "formats are skipped when `mesh` is false"),
            choice("mesh_normals", &OutputOptions::meshNormals,
                   {{"outward", int(MN::kOutward)}, {"inward", int(MN::kInward)}},
                   "side the normals of cave.glb face: `inward` shows the walls from inside in renderers that cull "
                   "back faces (games, walk-throughs); `cavesim run --mesh-normals` overrides"),
        }));

    ParamSection& siteSec = r.emplace_back(table<SiteSettings>(
        "site", site, "a real site: terrain, sinkholes, springs, geological surfaces",
        {
            real3("origin", &SiteSettings::origin, rng(-1e9, 1e9),
                  "world position of the block's low corner (voxel (0, 0, 0)'s corner) in the site's projected CRS: "
                  "easting, northing, elevation")
                .unitIs("m"),
            path("dem", &SiteSettings::dem,
                 "land surface (GeoTIFF, projected CRS in metres): voxels whose centre lies above it are air"),
            path("sinkholes", &SiteSettings::sinkholes,
                 "CSV with a header naming `x,y[,z],name[,pressure]` (world metres): each row a [[source]] voxel; "
                 "without z on the land surface"),
            path("springs", &SiteSettings::springs,
                 "CSV as `sinkholes`: each row a [[sink]] voxel; without z on the land surface"),
            path("base_of_limestone", &SiteSettings::baseOfLimestone,
                 "surface (GeoTIFF, or XYZ points `x y z` per line): voxels whose centre lies below it are insoluble"),
            path("water_table", &SiteSettings::waterTable,
                 "surface (GeoTIFF or XYZ points): read, checked and kept with the site (report); the water table of "
                 "stage 2 with `[hydrology] from_site = true`, else it does not "
                 "change the simulation"),
            real("sinkhole_pressure", &SiteSettings::sinkholePressure, rng(0, 1e6, "(]"),
                 "pressure of a sinkhole whose CSV row gives none (as [[source]] `pressure`)")
                .unitIs("relative"),
        }));
    siteSec.prose =
        "Places the block in a real site. Every file is in one projected CRS in metres (GeoTIFFs carry it; CSV\n"
        "and XYZ files are taken to be in the DEM's): `origin` puts the block's low corner at those world\n"
        "coordinates, so voxel `(i, j, k)` spans `origin + [i, i+1] · voxel_size` in x (and likewise y, z).\n"
        "A surface is sampled at each column's centre (GeoTIFF: bilinear; XYZ: inverse-distance weighting\n"
        "of the 8 nearest points, power 2). Voxels that are not karst rock — air above the DEM, insoluble\n"
        "rock below `base_of_limestone` — get porosity 0 and the flag `inert` (128): they hold no water, are\n"
        "never eroded and are never cave. Sinkholes and springs become sources and sinks after the\n"
        "`[[source]]` and `[[sink]]` entries; a point without z sits in the highest non-air voxel of its\n"
        "column. The index ↔ world transform is written to state.vdb (its transform), state.vti (Origin)\n"
        "and report.json (`world_from_index`); meshes, skeletons and the other files stay in block metres\n"
        "(add `origin`). Bad site input — a file that is not a GeoTIFF, a geographic CRS (degrees), CRSs\n"
        "that disagree, a point outside the block, a surface that leaves the block or does not cover it —\n"
        "is an error naming the file and the value, exit 2; so is a `[[source]]` or `[[sink]]` wholly in air\n"
        "or insoluble rock. Paths are relative to the scenario file's folder.";

    ParamSection& horizon = r.emplace_back(tableArray(
        "site.horizon", &Scenario::siteHorizons, 64, "inception horizons",
        {
            P(path("file", &SiteHorizon::file, "the horizon's surface (GeoTIFF or XYZ points), as `base_of_limestone`"))
                .isRequired("\"horizon.tif\""),
            real("thickness", &SiteHorizon::thickness, rng(0, 1e6, "(]"),
                 "slab thickness, measured vertically around the surface")
                .unitIs("voxels"),
            real("porosity", &SiteHorizon::porosity, rng(0, 1),
                 "porosity inside the slab (the larger of this and the rock's); flagged as fracture"),
        }));
    horizon.exampleCommented = true;
    horizon.prose =
        "A slab of raised porosity along a surface read from a file, like a `[[rock.plane]]` bedding "
        "plane that follows the site's geology. At most 64 horizons.";
    ParamSection& speleo = r.emplace_back(table<SpeleothemOptions>(
        "speleothems", speleothems,
        "stalactites and stalagmites (Short et al. 2005; Amorós-Tur & García-Fernández 2024)",
        {
            boolean(
                "enabled", &SpeleothemOptions::enabled,
                "grow speleothems on the cave after stage 2 and write `cave_decorated.*` (with `[output] mesh`) and "
                "`images/speleo_*.png` (with `[output] images`)"),
            boolean("drained", &SpeleothemOptions::drained,
                    "treat the whole cave as air-filled (there is no water table yet); `false` = water-filled: "
                    "nothing grows"),
            real("years", &SpeleothemOptions::years, rng(0, 1e6), "years of growth").unitIs("yr"),
            real("time_step", &SpeleothemOptions::timeStep, rng(0, 1e5),
                 "years between two updates of the speed field; 0 = the stable step, in which the fastest point "
                 "moves half a level-set voxel (the advection sub-steps at its own CFL limit within a step); "
                 "`years` / `time_step` may not exceed 10⁶ steps")
                .unitIs("yr")
                .defaultShown("0 (stable step)"),
            real("alpha", &SpeleothemOptions::alpha, rng(0, 100, "(]"),
                 "Short's rate constant α of v = α·l_Q·(l_Q/(r·sin θ))^(1/3) (chemistry of the drip water)")
                .unitIs("1/yr"),
            real("l_q", &SpeleothemOptions::lQ, rng(1e-6, 1e-2), "Short's characteristic length l_Q").unitIs("m"),
            real("voxel_size", &SpeleothemOptions::voxelSize, rng(1e-4, 1),
                 "voxel edge of the decoration level set (the cave surface resampled finer); "
                 "run time and mesh size grow as its inverse square")
                .unitIs("m"),
            real("convexity", &SpeleothemOptions::convexity, rng(0, 1e4),
                 "least mean curvature of the ceiling (convex downward) for a point to belong to a stalactite "
                 "(the paper's ε_s)")
                .unitIs("1/m"),
            real("min_size", &SpeleothemOptions::minSize, rng(0, 100),
                 "least horizontal radius of a convex ceiling patch around its lowest point for it to grow")
                .unitIs("m"),
            real("tip_radius", &SpeleothemOptions::tipRadius, rng(0, 10),
                 "radius ε around a stalactite's axis inside which the tip translates down at Short's tip speed "
                 "α·l_Q instead of the singular law; outside, r·sin θ is floored at it; 0 = two voxels")
                .unitIs("m")
                .defaultShown("0 (2 voxels)"),
            real("roughness", &SpeleothemOptions::roughness, rng(0, 10),
                 "amplitude of the seeded relief added to downward-facing rock before growth (the cave's "
                 "smooth surface has no centimetre relief to start stalactites from); 0 = none")
                .unitIs("m"),
            real("roughness_scale", &SpeleothemOptions::roughnessScale, rng(1e-3, 100, "(]"),
                 "feature size of that relief")
                .unitIs("m"),
            real("drip_variability", &SpeleothemOptions::dripVariability, rng(0, 2),
                 "relative spread of α between drip sites: α·exp(variability·g), g a smooth seeded noise of the "
                 "tip's position in [-1, 1]"),
            integer("seed", &SpeleothemOptions::seed, rng(0, double(kInt64Max)),
                    "seeds the relief and the drip variability")
                .rangeShown("0 – 2⁶³−1"),
            boolean("stalagmites", &SpeleothemOptions::stalagmites,
                    "grow a stalagmite on the floor below each active stalactite tip"),
            real("stalagmite_rate", &SpeleothemOptions::stalagmiteRate, rng(0, 100),
                 "stalagmite apex growth rate as a multiple of the tip speed of the stalactite dripping on it"),
            real("stalagmite_radius", &SpeleothemOptions::stalagmiteRadius, rng(1e-3, 10, "(]"),
                 "stalagmite equilibrium radius: the growth rate falls as exp(-d²/(2R²)) with the horizontal "
                 "distance d from the drip axis")
                .unitIs("m"),
            integer("frames", &SpeleothemOptions::frames, rng(0, 64),
                    "growth animation frames (`images/speleo_perspective_NN.png`, `images/speleo_closeup_NN.png`); "
                    "none with `[output] images = false`, where giving a number above 0 is an error"),
        }));
    speleo.prose =
        "Speleothems grow after stage 2 on a finer level set of the cave surface; the law, its 3D reading\n"
        "and its limits are in `docs/speleothems.md`.";
    return r;
}

}  // namespace

const Param& ParamSection::param(const std::string& k) const {
    for (const Param& p : params)
        if (p.key == k) return p;
    throw RuntimeError("parameter registry: no key '" + k + "' in section '" + path + "'");
}

std::string ParamSection::header() const {
    return isArray ? "[[" + path + "]]" : "[" + path + "]";
}

std::string ParamSection::qualified(const std::string& k) const {
    return path.empty() ? k : path + "." + k;
}

const std::vector<ParamSection>& scenarioParameters() {
    static const std::vector<ParamSection> registry = makeRegistry();
    return registry;
}

const ParamSection& paramSection(const std::string& path) {
    for (const ParamSection& s : scenarioParameters())
        if (s.path == path) return s;
    throw RuntimeError("parameter registry: no section '" + path + "'");
}

std::optional<ParamLocation> locateParam(const Scenario& scenario, const void* field) {
    for (const ParamSection& s : scenarioParameters())
        for (std::size_t i = 0; i < s.count(scenario); ++i)
            for (const Param& p : s.params)
                if (p.address(s.record(scenario, i)) == field) return ParamLocation{&s, &p, i};
    return std::nullopt;
}

std::pair<const ParamSection*, const Param*> findParam(const Scenario& scenario, const void* field) {
    const std::optional<ParamLocation> at = locateParam(scenario, field);
    if (!at) throw RuntimeError("parameter registry: not a registered field");
    return {at->section, at->param};
}

namespace {

std::string realText(double v) {
    std::string t = shortestText(v);
    if (t.find_first_of(".eEni") == std::string::npos) t += ".0";
    return t;
}

template <typename T, typename F>
std::string listText(const std::vector<T>& v, F each) {
    std::string out = "[";
    for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + each(v[i]);
    return out + "]";
}

/// A number for the reference: 10⁶ rather than 1000000.
std::string docNumber(double v) {
    static const char* kSup[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
    const double a = std::fabs(v);
    if (a >= 1e4) {
        const int e = int(std::lround(std::log10(a)));
        if (e < 10 && std::pow(10.0, e) == a) return std::string(v < 0 ? "-" : "") + "10" + kSup[e];
    }
    return shortestText(v);
}

std::string typeText(const Param& p) {
    switch (p.type) {
        case ParamType::kBool:
            return "bool";
        case ParamType::kInt:
            return "integer";
        case ParamType::kReal:
            return "float";
        case ParamType::kString:
        case ParamType::kChoice:
            return "string";
        case ParamType::kInt3:
            return "[int, int, int]";
        case ParamType::kReal3:
            return "[float ×3]";
        case ParamType::kReal3List:
            return "[[float ×3], …]";
        case ParamType::kChoiceList:
            return "[string, …]";
        case ParamType::kIntList:
            return "[int, …]";
        case ParamType::kVoxel:
            return "[int ×3]";
        case ParamType::kVoxelBox:
            return "[[int ×3], [int ×3]]";
        case ParamType::kPath:
            return "string (path)";
    }
    return "?";
}

std::string choicesText(const Param& p) {
    std::string out;
    for (const auto& c : p.choices) out += (out.empty() ? "`\"" : ", `\"") + std::string(c.name) + "\"`";
    return out;
}

std::string rangeText(const Param& p);

}  // namespace

std::string paramRangeText(const Param& p) {
    return rangeText(p);
}

namespace {

std::string rangeText(const Param& p) {
    if (!p.rangeText.empty()) return p.rangeText;
    const ParamRange& r = p.range;
    switch (p.type) {
        case ParamType::kBool:
            return "–";
        case ParamType::kChoice:
            return choicesText(p);
        case ParamType::kChoiceList:
            return "distinct values out of " + choicesText(p);
        case ParamType::kInt:
        case ParamType::kInt3:
        case ParamType::kIntList:
            return (p.type == ParamType::kInt ? "" : "each ") + docNumber(r.lo) + "–" + docNumber(r.hi);
        default:
            if (r.domainScaled) return "within ±4 × the largest domain size";
            return std::string(p.type == ParamType::kReal ? "" : "each ") + (r.loOpen ? "(" : "[") + docNumber(r.lo) +
                   ", " + docNumber(r.hi) + (r.hiOpen ? ")" : "]");
    }
}

std::string defaultText(const ParamSection& s, const Param& p) {
    if (!p.defaultText.empty()) return p.defaultText;
    if (p.required) return "*required*";
    if (p.type == ParamType::kVoxelBox) return "–";
    const std::string v = paramValueText(p.get(s.defaults()));
    return v.find('"') == std::string::npos ? v : "`" + v + "`";
}

std::string sectionTitle(const ParamSection& s) {
    if (s.path.empty()) return "## " + s.heading;
    const bool nested = s.path.find('.') != std::string::npos;
    return std::string(nested ? "### `" : "## `") + s.header() + "`" + (s.heading.empty() ? "" : " — " + s.heading);
}

}  // namespace

std::string paramValueText(const ParamValue& v) {
    struct Visitor {
        std::string operator()(bool b) const { return b ? "true" : "false"; }
        std::string operator()(std::int64_t i) const { return std::to_string(i); }
        std::string operator()(double d) const { return realText(d); }
        std::string operator()(const std::string& s) const { return "\"" + s + "\""; }
        std::string operator()(const std::vector<std::int64_t>& a) const {
            if (a.size() == 6)
                return "[" + (*this)(std::vector<std::int64_t>(a.begin(), a.begin() + 3)) + ", " +
                       (*this)(std::vector<std::int64_t>(a.begin() + 3, a.end())) + "]";
            return listText(a, [](std::int64_t i) { return std::to_string(i); });
        }
        std::string operator()(const std::vector<double>& a) const { return listText(a, realText); }
        std::string operator()(const std::vector<std::string>& a) const {
            return listText(a, [](const std::string& s) { return "\"" + s + "\""; });
        }
        std::string operator()(const std::vector<Vec3d>& a) const {
            return listText(a,
                            [](const Vec3d& p) { return listText(std::vector<double>(p.begin(), p.end()), realText); });
        }
    };
    return std::visit(Visitor{}, v);
}

std::string scenarioReferenceMarkdown() {
    std::ostringstream md;
    const auto& reg = scenarioParameters();
    md << "# Scenario file format\n\n" << reg.front().prose << "\n";
    for (const ParamSection& s : reg) {
        md << "\n" << sectionTitle(s) << "\n\n";
        if (!s.path.empty() && !s.prose.empty()) md << s.prose << "\n\n";
        md << "| key | type | default | unit | range | meaning |\n|---|---|---|---|---|---|\n";
        for (const Param& p : s.params)
            md << "| `" << p.key << "` | " << typeText(p) << " | " << defaultText(s, p) << " | " << p.unit << " | "
               << rangeText(p) << " | " << p.description << " |\n";
        if (!s.notes.empty()) md << "\n" << s.notes << "\n";
    }
    return md.str();
}

std::string exampleScenarioToml() {
    std::ostringstream out;
    out << "# A complete scenario: every key at its default (`cavesim reference --example`).\n"
           "# Each comment gives the meaning, the unit and the allowed range; docs/scenario-format.md has more.\n";
    for (const ParamSection& s : scenarioParameters()) {
        out << "\n";
        const std::string off = s.exampleCommented ? "# " : "";
        if (!s.path.empty())
            out << off << s.header() << (s.isArray ? "  # one entry of possibly many" : "")
                << (!s.exampleCommented     ? ""
                    : s.exampleNote.empty() ? " (it needs its files: remove the '# ')"
                                            : " (" + s.exampleNote + ")")
                << "\n";
        for (const Param& p : s.params) {
            out << "# " << p.description << " (unit: " << p.unit << "; range: " << rangeText(p) << ")\n";
            if (p.type == ParamType::kVoxelBox) {
                out << "# " << p.key << " = [[0, 0, 0], [1, 1, 1]]\n";
                continue;
            }
            out << off << p.key << " = " << (p.example.empty() ? paramValueText(p.get(s.defaults())) : p.example)
                << "\n";
        }
    }
    return out.str();
}

std::string parameterTableMarkdown(const Scenario& scenario) {
    std::ostringstream md;
    md << "| key | value |\n|---|---|\n";
    for (const ParamSection& s : scenarioParameters()) {
        if (s.isArray) continue;
        for (const Param& p : s.params) {
            const ParamValue v = p.get(s.record(scenario, 0));
            const ParamValue d = p.get(s.defaults());
            md << "| `" << s.qualified(p.key) << "` | ";
            if (v == d)
                md << paramValueText(v);
            else
                md << "**" << paramValueText(v) << "** (default " << paramValueText(d) << ")";
            md << " |\n";
        }
    }
    return md.str();
}

}  // namespace cavesim
