#include "sim/scenario_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "core/error.h"
#include "sim/default_scenario.h"

namespace cavesim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

template <typename E>
struct EnumName {
    E value;
    const char* name;
};
constexpr EnumName<ProtosinkMode> kProtosinkNames[] = {{ProtosinkMode::kBoundary, "boundary"}, {ProtosinkMode::kClustered, "clustered"}};
constexpr EnumName<ZoneSpeed> kZoneSpeedNames[] = {{ZoneSpeed::kUniform, "uniform"}, {ZoneSpeed::kPorosity, "porosity"}};
constexpr EnumName<GridFace> kFaceNames[] = {{GridFace::kMinusX, "-x"}, {GridFace::kPlusX, "+x"}, {GridFace::kMinusY, "-y"},
                                             {GridFace::kPlusY, "+y"},  {GridFace::kMinusZ, "-z"}, {GridFace::kPlusZ, "+z"}};
constexpr EnumName<TransportWeight> kWeightNames[] = {{TransportWeight::kProportional, "proportional"}, {TransportWeight::kUniform, "uniform"}};
constexpr EnumName<FlowBlending> kBlendingNames[] = {{FlowBlending::kMax, "max"}, {FlowBlending::kSplit, "split"}};
constexpr EnumName<MeshStyle> kMeshStyleNames[] = {{MeshStyle::kSmooth, "smooth"}, {MeshStyle::kVoxel, "voxel"}};
constexpr EnumName<CaveExtent> kCaveNames[] = {{CaveExtent::kChannels, "channels"}, {CaveExtent::kWithProtochannels, "with_protochannels"}};
constexpr EnumName<PlaneKind> kPlaneKindNames[] = {{PlaneKind::kBedding, "bedding"}, {PlaneKind::kFracture, "fracture"}};

template <typename E, std::size_t N>
std::string nameOf(const EnumName<E> (&table)[N], E v) {
    for (const auto& e : table)
        if (e.value == v) return e.name;
    return "?";
}

/// Shortest decimal text that reads back as the same double (0.3, not 0.29999999999999999).
std::string shortest(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

/// A string value as it would be written in TOML: quotes and control characters escaped, so an
/// error message stays on one line and shows what the file holds.
std::string quoted(const std::string& v) {
    std::string out = "\"";
    for (unsigned char c : v) {
        if (c == '"' || c == '\\') {
            out += '\\';
            out += char(c);
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c < 0x20 || c == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", c);
            out += buf;
        } else {
            out += char(c);
        }
    }
    return out + '"';
}

void describeInto(const toml::node& n, std::string& out) {
    if (n.is_string()) {
        out += quoted(n.as_string()->get());
    } else if (n.is_floating_point()) {
        // A float is shown as one (4.0, not 4), so "must be a whole number" does not quote a
        // value that looks whole.
        std::string t = shortest(n.as_floating_point()->get());
        if (t.find_first_of(".eEni") == std::string::npos) t += ".0";
        out += t;
    } else if (n.is_integer()) {
        out += std::to_string(n.as_integer()->get());
    } else if (n.is_boolean()) {
        out += n.as_boolean()->get() ? "true" : "false";
    } else if (n.is_array()) {
        out += '[';
        bool first = true;
        for (const toml::node& e : *n.as_array()) {
            if (!first) out += ", ";
            first = false;
            describeInto(e, out);
        }
        out += ']';
    } else if (n.is_table()) {
        out += "(a table)";
    } else {
        std::ostringstream os;
        n.visit([&os](auto&& v) { os << v; });
        out += os.str();
    }
}

/// `s` cut to at most `keep` bytes plus "..." when longer than `limit`, never inside a UTF-8 character.
std::string shortened(const std::string& s, std::size_t limit, std::size_t keep) {
    if (s.size() <= limit) return s;
    std::size_t cut = keep;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xC0) == 0x80) --cut;  // continuation byte
    return s.substr(0, cut) + "...";
}

std::string describe(const toml::node& n) {
    std::string s;
    describeInto(n, s);
    return shortened(s, 60, 57);
}

/// The deepest run of dotted key parts (`a.b.c` is 3) outside strings and comments. toml++
/// recurses once per part and overflows the stack on keys of ~100 000 parts; cavesim's keys have 3.
int deepestDottedKey(std::string_view t) {
    int deepest = 0, dots = 0;
    for (std::size_t c = 0; c < t.size(); ++c) {
        const char ch = t[c];
        if (ch == '#') {  // comment to the end of the line
            while (c < t.size() && t[c] != '\n') ++c;
            dots = 0;
        } else if (ch == '"' || ch == '\'') {
            const bool triple = t.substr(c, 3) == std::string(3, ch);
            const std::string_view close = triple ? t.substr(c, 3) : t.substr(c, 1);
            c += close.size();
            while (c < t.size() && t.substr(c, close.size()) != close) c += (ch == '"' && t[c] == '\\') ? 2 : 1;
            c += close.size() - 1;  // on the closing quote; a quoted part continues the run
            // A multi-line string may end in up to two more quotes ("""x"""" is the string x").
            for (int extra = 0; triple && extra < 2 && c + 1 < t.size() && t[c + 1] == ch; ++extra) ++c;
        } else if (ch == '.') {
            deepest = std::max(deepest, ++dots + 1);
        } else if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == ' ' || ch == '\t')) {
            dots = 0;
        }
    }
    return deepest;
}

/// Reads one TOML table against a fixed set of keys; everything it reports names file, line, key.
class TableReader {
public:
    TableReader(const toml::table& table, std::string prefix, const std::string& file)
        : table_(table), prefix_(std::move(prefix)), file_(file) {}

    [[noreturn]] void fail(const std::string& key, const toml::node* node, const std::string& allowed) const {
        std::ostringstream os;
        const int line = node ? int(node->source().begin.line) : int(table_.source().begin.line);
        os << file_;
        if (line > 0) os << ":" << line;
        os << ": key '" << qualified(key) << "'";
        if (node) os << " = " << describe(*node);
        os << ": " << allowed;
        throw InputError(os.str());
    }

    std::string qualified(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
    const std::string& file() const { return file_; }

    const toml::node* get(const std::string& key) {
        seen_.insert(key);
        return table_.get(key);
    }

    double number(const std::string& key, double def, double lo, double hi, bool loOpen = false,
                  bool hiOpen = false) {
        const toml::node* n = get(key);
        if (!n) return def;
        return toNumber(key, *n, lo, hi, loOpen, hiOpen);
    }

    double toNumber(const std::string& key, const toml::node& n, double lo, double hi, bool loOpen,
                    bool hiOpen) const {
        double v = 0;
        if (auto i = n.as_integer()) v = double(i->get());
        else if (auto f = n.as_floating_point()) v = f->get();
        else fail(key, &n, "must be a number " + range(lo, hi, loOpen, hiOpen));
        const bool ok = std::isfinite(v) && (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
        if (!ok) fail(key, &n, "must be a number " + range(lo, hi, loOpen, hiOpen));
        return v;
    }

    long integer(const std::string& key, long def, long lo, long hi) {
        const toml::node* n = get(key);
        if (!n) return def;
        return toInteger(key, *n, lo, hi);
    }

    long toInteger(const std::string& key, const toml::node& n, long lo, long hi) const {
        auto i = n.as_integer();
        const std::string allowed = "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (!i) fail(key, &n, allowed);
        const long v = long(i->get());
        if (v < lo || v > hi) fail(key, &n, allowed);
        return v;
    }

    bool boolean(const std::string& key, bool def) {
        const toml::node* n = get(key);
        if (!n) return def;
        auto b = n->as_boolean();
        if (!b) fail(key, n, "must be true or false");
        return b->get();
    }

    template <typename E, std::size_t N>
    E choice(const std::string& key, E def, const EnumName<E> (&allowed)[N]) {
        const toml::node* n = get(key);
        if (!n) return def;
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + std::string(a.name) + "\"";
        auto s = n->as_string();
        if (!s) fail(key, n, "must be one of " + list);
        for (const auto& a : allowed)
            if (s->get() == a.name) return a.value;
        fail(key, n, "must be one of " + list);
    }

    Vec3d vec3(const std::string& key, const Vec3d& def, double lo, double hi, bool required = false) {
        const toml::node* n = get(key);
        if (!n) {
            if (required) fail(key, nullptr, "is required: an array of 3 numbers");
            return def;
        }
        return toVec3(key, *n, lo, hi);
    }

    Vec3d toVec3(const std::string& key, const toml::node& n, double lo, double hi) const {
        auto a = n.as_array();
        const std::string allowed = "must be an array of 3 numbers, each " + range(lo, hi, false, false);
        if (!a || a->size() != 3) fail(key, &n, allowed);
        Vec3d v{};
        for (std::size_t c = 0; c < 3; ++c) {
            const toml::node& e = *a->get(c);
            if (e.as_integer()) v[c] = double(e.as_integer()->get());
            else if (e.as_floating_point()) v[c] = e.as_floating_point()->get();
            else fail(key, &n, allowed);
            if (!std::isfinite(v[c]) || v[c] < lo || v[c] > hi) fail(key, &n, allowed);
        }
        return v;
    }

    std::array<int, 3> ivec3(const std::string& key, const toml::node& n, long lo, long hi) const {
        auto a = n.as_array();
        const std::string allowed =
            "must be an array of 3 whole numbers in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (!a || a->size() != 3) fail(key, &n, allowed);
        std::array<int, 3> v{};
        for (std::size_t c = 0; c < 3; ++c) {
            auto i = a->get(c)->as_integer();
            if (!i || i->get() < lo || i->get() > hi) fail(key, &n, allowed);
            v[c] = int(i->get());
        }
        return v;
    }

    const toml::table* subtable(const std::string& key) {
        const toml::node* n = get(key);
        if (!n) return nullptr;
        if (!n->is_table()) fail(key, n, "must be a table");
        return n->as_table();
    }

    /// An array of tables (`[[key]]`); empty when absent.
    std::vector<const toml::table*> tableArray(const std::string& key, std::size_t maxEntries = 4096) {
        std::vector<const toml::table*> out;
        const toml::node* n = get(key);
        if (!n) return out;
        auto a = n->as_array();
        if (!a) fail(key, n, "must be an array of tables, written [[" + qualified(key) + "]]");
        if (a->size() > maxEntries)
            fail(key, nullptr, "at most " + std::to_string(maxEntries) + " [[" + qualified(key) + "]] entries, found " +
                                   std::to_string(a->size()));
        for (const toml::node& e : *a) {
            if (!e.is_table()) fail(key, &e, "every entry must be a table, written [[" + qualified(key) + "]]");
            out.push_back(e.as_table());
        }
        return out;
    }

    /// Rejects every key that was not asked for.
    void finish(const std::vector<std::string>& known) const {
        for (auto&& [k, v] : table_) {
            const std::string key(k.str());
            if (seen_.count(key)) continue;
            std::string list;
            for (const auto& a : known) list += (list.empty() ? "" : ", ") + a;
            std::ostringstream os;
            os << file_;
            if (k.source().begin.line > 0) os << ":" << k.source().begin.line;
            // The key as written, escaped and shortened: the message stays one readable line.
            std::string shown = quoted(qualified(key));
            shown = shortened(shown.substr(1, shown.size() - 2), 60, 57);
            os << ": unknown key '" << shown << "' = " << describe(v) << ": allowed keys here are " << list;
            throw InputError(os.str());
        }
    }

private:
    static std::string fmt(double v) {
        if (v == kInf) return "inf";
        std::ostringstream os;
        os << v;
        return os.str();
    }
    static std::string range(double lo, double hi, bool loOpen, bool hiOpen) {
        return std::string("in ") + (loOpen ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + (hiOpen ? ")" : "]");
    }

    const toml::table& table_;
    std::string prefix_;
    const std::string& file_;
    std::set<std::string> seen_;
};

VoxelBox readBox(TableReader& r, const std::array<int, 3>& size, const std::string& what) {
    const toml::node* at = r.get("at");
    const toml::node* box = r.get("box");
    if (at && box) r.fail("box", box, "give either 'at' or 'box', not both");
    if (!at && !box) r.fail("at", nullptr, "a " + what + " needs 'at = [x, y, z]' or 'box = [[x0, y0, z0], [x1, y1, z1]]'");
    const long big = 1 << 20;
    VoxelBox b;
    if (at) {
        b.lo = r.ivec3("at", *at, -big, big);
        b.hi = b.lo;
    } else {
        auto a = box->as_array();
        if (!a || a->size() != 2) r.fail("box", box, "must be [[x0, y0, z0], [x1, y1, z1]] (inclusive voxel indices)");
        b.lo = r.ivec3("box", *a->get(0), -big, big);
        b.hi = r.ivec3("box", *a->get(1), -big, big);
    }
    for (int c = 0; c < 3; ++c) {
        const toml::node* n = at ? at : box;
        const std::string key = at ? "at" : "box";
        if (b.lo[c] > b.hi[c]) r.fail(key, n, "box corners must satisfy x0 <= x1, y0 <= y1, z0 <= z1");
        if (b.lo[c] < 0 || b.hi[c] >= size[c]) {
            r.fail(key, n,
                   "the " + what + " must lie inside the domain: indices 0.." + std::to_string(size[0] - 1) + ", 0.." +
                       std::to_string(size[1] - 1) + ", 0.." + std::to_string(size[2] - 1));
        }
    }
    return b;
}

Scenario parseTable(const toml::table& root, const std::string& file) {
    Scenario s;
    s.path = file;
    TableReader top(root, "", file);
    if (const toml::node* n = top.get("name")) {
        auto str = n->as_string();
        const std::string allowed = "must be a string of 1-64 letters, digits, '-' or '_'";
        if (!str || str->get().empty() || str->get().size() > 64) top.fail("name", n, allowed);
        for (char c : str->get())
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) top.fail("name", n, allowed);
        s.name = str->get();
    }
    s.seed = std::uint64_t(top.integer("seed", 1, 0, std::numeric_limits<long>::max()));

    if (const toml::table* t = top.subtable("domain")) {
        TableReader r(*t, "domain", file);
        if (const toml::node* n = r.get("size")) s.size = r.ivec3("size", *n, 1, 1024);
        s.voxelSize = r.number("voxel_size", 1.0, 1e-3, 1e4);
        r.finish({"size", "voxel_size"});
    }
    const double cells = double(s.size[0]) * s.size[1] * s.size[2];
    if (cells > 16e6) {  // stage 2 holds about 300 bytes per voxel: 16 M voxels need about 5 GB
        top.fail("domain", root.get("domain"), "domain.size gives " + std::to_string(long(cells)) +
                                                   " voxels; at most 16,000,000 are allowed (stage 2 needs about 300 bytes per voxel)");
    }
    const double ext = std::max({s.size[0], s.size[1], s.size[2]}) * 4.0;

    if (const toml::table* t = top.subtable("rock")) {
        TableReader r(*t, "rock", file);
        s.rockPorosity = r.number("porosity", s.rockPorosity, 0, 1);
        if (const toml::table* nt = r.subtable("noise")) {
            TableReader nr(*nt, "rock.noise", file);
            s.noise.amplitude = nr.number("amplitude", 0.0, 0, 1);
            s.noise.scale = nr.number("scale", 8.0, 0.01, 1e6);
            s.noise.octaves = int(nr.integer("octaves", 3, 1, 8));
            nr.finish({"amplitude", "scale", "octaves"});
        }
        for (const toml::table* st : r.tableArray("sphere")) {
            TableReader sr(*st, "rock.sphere", file);
            SphereObstacle o;
            o.center = sr.vec3("center", o.center, -ext, ext, true);
            o.radius = sr.number("radius", o.radius, 0, 1e6, true);
            o.corePorosity = sr.number("core_porosity", o.corePorosity, 0, 1);
            sr.finish({"center", "radius", "core_porosity"});
            s.spheres.push_back(o);
        }
        for (const toml::table* pt : r.tableArray("plane", 1024)) {
            TableReader pr(*pt, "rock.plane", file);
            PlaneFeature p;
            p.point = pr.vec3("point", p.point, -ext, ext, true);
            p.normal = pr.vec3("normal", p.normal, -1e6, 1e6);
            if (std::hypot(p.normal[0], p.normal[1], p.normal[2]) < 1e-9) pr.fail("normal", pt->get("normal"), "must not be zero");
            p.thickness = pr.number("thickness", p.thickness, 0, 1e6, true);
            p.porosity = pr.number("porosity", p.porosity, 0, 1);
            p.extent = pr.number("extent", 0.0, 0, 1e6);
            p.kind = pr.choice("kind", p.kind, kPlaneKindNames);
            pr.finish({"point", "normal", "thickness", "porosity", "extent", "kind"});
            s.planes.push_back(p);
        }
        std::size_t channelPoints = 0;  // all polylines together: the effective scenario rewrites each
        for (const toml::table* ct : r.tableArray("channel", 1024)) {
            TableReader cr(*ct, "rock.channel", file);
            ChannelFeature c;
            const toml::node* pts = cr.get("points");
            if (!pts) cr.fail("points", nullptr, "is required: an array of at least 2 points [x, y, z]");
            auto a = pts->as_array();
            if (!a || a->size() < 2) cr.fail("points", pts, "must be an array of at least 2 points [x, y, z]");
            channelPoints += a->size();
            if (channelPoints > 65536)
                cr.fail("points", pts, "all [[rock.channel]] polylines together may have at most 65536 points");
            for (const toml::node& e : *a) c.points.push_back(cr.toVec3("points", e, -ext, ext));
            c.radius = cr.number("radius", c.radius, 0, 1e6);
            c.porosity = cr.number("porosity", c.porosity, 0, 1);
            c.protochannel = cr.boolean("protochannel", c.protochannel);
            cr.finish({"points", "radius", "porosity", "protochannel"});
            s.channels.push_back(c);
        }
        r.finish({"porosity", "noise", "sphere", "plane", "channel"});
    }

    constexpr std::size_t kMaxTerminals = 256;  // each source marches its own zone front over the grid
    for (const toml::table* t : top.tableArray("source", std::numeric_limits<std::size_t>::max())) {
        TableReader r(*t, "source", file);
        if (s.sources.size() == kMaxTerminals)
            throw InputError(file + ":" + std::to_string(t->source().begin.line) + ": key 'source': at most " +
                             std::to_string(kMaxTerminals) +
                             " [[source]] entries (one [[source]] may be a box of many voxels)");
        SourceSpec src;
        src.line = int(t->source().begin.line);
        src.box = readBox(r, s.size, "source");
        src.pressure = r.number("pressure", 1.0, 0, 1e6, true);
        r.finish({"at", "box", "pressure"});
        s.sources.push_back(src);
    }
    for (const toml::table* t : top.tableArray("sink", std::numeric_limits<std::size_t>::max())) {
        TableReader r(*t, "sink", file);
        if (s.sinks.size() == kMaxTerminals)
            throw InputError(file + ":" + std::to_string(t->source().begin.line) + ": key 'sink': at most " +
                             std::to_string(kMaxTerminals) +
                             " [[sink]] entries (one [[sink]] may be a box of many voxels)");
        SinkSpec snk;
        snk.line = int(t->source().begin.line);
        snk.box = readBox(r, s.size, "sink");
        r.finish({"at", "box"});
        s.sinks.push_back(snk);
    }

    if (const toml::table* t = top.subtable("stage1")) {
        TableReader r(*t, "stage1", file);
        Stage1Options& g = s.stage1;
        g.enabled = r.boolean("enabled", g.enabled);
        g.protosinks = r.choice("protosinks", g.protosinks, kProtosinkNames);
        g.clusters = int(r.integer("clusters", g.clusters, 1, 64));
        g.clusterRadius = r.number("cluster_radius", g.clusterRadius, 0, 1e6);
        if (const toml::node* n = r.get("aim")) {
            auto a = n->as_array();
            if (!a) r.fail("aim", n, "must be an array of points [x, y, z]");
            if (a->size() > 1024) r.fail("aim", n, "must have at most 1024 points");
            for (const toml::node& e : *a) g.aim.push_back(r.toVec3("aim", e, -ext, ext));
        }
        g.permeability = r.choice("permeability", g.permeability, kZoneSpeedNames);
        g.protochannelPorosity = r.number("protochannel_porosity", g.protochannelPorosity, 0, 1);
        g.capacityExponent = r.number("capacity_exponent", g.capacityExponent, 0, 8, true);
        g.maxGraphVoxels = r.integer("max_graph_voxels", g.maxGraphVoxels, 1, 1000000000L);
        if (const toml::node* n = r.get("boundary_faces")) {
            const std::string allowed =
                "must be an array of distinct grid faces out of \"-x\", \"+x\", \"-y\", \"+y\", \"-z\", \"+z\" "
                "(may be empty)";
            auto a = n->as_array();
            if (!a) r.fail("boundary_faces", n, allowed);
            g.boundaryFaces.clear();
            for (const toml::node& e : *a) {
                auto str = e.as_string();
                if (!str) r.fail("boundary_faces", n, allowed);
                const auto face = std::find_if(std::begin(kFaceNames), std::end(kFaceNames),
                                               [&](const auto& f) { return str->get() == f.name; });
                if (face == std::end(kFaceNames) ||
                    std::find(g.boundaryFaces.begin(), g.boundaryFaces.end(), face->value) != g.boundaryFaces.end())
                    r.fail("boundary_faces", n, allowed);
                g.boundaryFaces.push_back(face->value);
            }
        }
        g.protosinkShare = r.number("protosink_share", g.protosinkShare, 0, 1, true);
        g.branchFlow = r.number("branch_flow", g.branchFlow, 0, 1);
        g.resistanceNoise = r.number("resistance_noise", g.resistanceNoise, 0, 1);
        r.finish({"enabled", "protosinks", "clusters", "cluster_radius", "aim", "permeability",
                  "protochannel_porosity", "capacity_exponent", "max_graph_voxels", "boundary_faces",
                  "protosink_share", "branch_flow", "resistance_noise"});
    }
    if (const toml::table* t = top.subtable("stage2")) {
        TableReader r(*t, "stage2", file);
        Stage2Options& g = s.stage2;
        g.enabled = r.boolean("enabled", g.enabled);
        g.iterations = int(r.integer("iterations", g.iterations, 0, 1000000));
        g.pRate = r.number("p_rate", g.pRate, 0, 1e6, true);
        g.pRateChannel = r.number("p_rate_channel", g.pRateChannel, 0, 1e6, true);
        if (g.pRateChannel > g.pRate) {
            // Blame the key the file gives; if it gives only p_rate, the default channel rate is the bound.
            if (t->get("p_rate_channel"))
                r.fail("p_rate_channel", t->get("p_rate_channel"),
                       "must not exceed p_rate (" + shortest(g.pRate) + "): channels resist flow less than rock");
            r.fail("p_rate", t->get("p_rate"),
                   "must be at least p_rate_channel (" + shortest(g.pRateChannel) +
                       ", the default): channels resist flow less than rock; lower p_rate_channel too");
        }
        g.w0 = r.number("w0", g.w0, 0, 10);
        g.wa = r.number("wa", g.wa, 0, 100);
        g.m = r.number("m", g.m, 0, 4, true);
        g.pressureScale = r.number("pressure_scale", g.pressureScale, 0, 1e9);
        g.channelThreshold = r.number("channel_threshold", g.channelThreshold, 0, 1, true);
        g.protochannelPorosity = r.number("protochannel_porosity", g.protochannelPorosity, 0, 1);
        g.sourcePorosity = r.number("source_porosity", g.sourcePorosity, 0, 1, true);
        g.weight = r.choice("weight", g.weight, kWeightNames);
        g.blending = r.choice("blending", g.blending, kBlendingNames);
        if (const toml::node* n = r.get("snapshots")) {
            auto a = n->as_array();
            if (!a) r.fail("snapshots", n, "must be an array of iteration numbers");
            if (a->size() > 32) r.fail("snapshots", n, "must list at most 32 iterations");
            for (const toml::node& e : *a) g.snapshots.push_back(int(r.toInteger("snapshots", e, 0, 1000000)));
        }
        r.finish({"enabled", "iterations", "p_rate", "p_rate_channel", "w0", "wa", "m", "pressure_scale",
                  "channel_threshold", "protochannel_porosity", "source_porosity", "weight", "blending",
                  "snapshots"});
    }
    if (const toml::table* t = top.subtable("output")) {
        TableReader r(*t, "output", file);
        OutputOptions& o = s.output;
        o.meshStyle = r.choice("mesh_style", o.meshStyle, kMeshStyleNames);
        o.imageWidth = int(r.integer("image_width", o.imageWidth, 256, 8192));
        o.images = r.boolean("images", o.images);
        o.mesh = r.boolean("mesh", o.mesh);
        o.cave = r.choice("cave", o.cave, kCaveNames);
        r.finish({"mesh_style", "image_width", "images", "mesh", "cave"});
    }
    top.finish({"name", "seed", "domain", "rock", "source", "sink", "stage1", "stage2", "output"});
    validateScenario(s);
    return s;
}

bool boxesOverlap(const VoxelBox& a, const VoxelBox& b) {
    for (int c = 0; c < 3; ++c)
        if (a.hi[c] < b.lo[c] || b.hi[c] < a.lo[c]) return false;
    return true;
}

std::string where(const Scenario& s, int line) {
    return s.path + (line > 0 ? ":" + std::to_string(line) : std::string());
}

}  // namespace

void validateScenario(const Scenario& s) {
    for (std::size_t i = 0; i < s.sources.size(); ++i) {
        for (int c = 0; c < 3; ++c) {
            if (s.sources[i].box.lo[c] < 0 || s.sources[i].box.hi[c] >= s.size[c])
                throw InputError(where(s, s.sources[i].line) + ": [[source]] " + std::to_string(i + 1) +
                                 " lies outside the domain");
        }
        for (std::size_t j = 0; j < s.sinks.size(); ++j) {
            if (boxesOverlap(s.sources[i].box, s.sinks[j].box)) {
                throw InputError(where(s, s.sinks[j].line) + ": key 'sink' (entry " + std::to_string(j + 1) +
                                 ") overlaps [[source]] entry " + std::to_string(i + 1) + " (line " +
                                 std::to_string(s.sources[i].line) + "): a voxel cannot be both source and sink");
            }
        }
    }
    for (std::size_t j = 0; j < s.sinks.size(); ++j)
        for (int c = 0; c < 3; ++c)
            if (s.sinks[j].box.lo[c] < 0 || s.sinks[j].box.hi[c] >= s.size[c])
                throw InputError(where(s, s.sinks[j].line) + ": [[sink]] " + std::to_string(j + 1) +
                                 " lies outside the domain");
    if ((s.stage1.enabled || s.stage2.enabled) && s.sources.empty()) {
        throw InputError(s.path + ": key 'source': at least one [[source]] is needed when a stage is enabled");
    }
    if (s.stage2.enabled && s.sinks.empty()) {
        throw InputError(s.path + ": key 'stage2.enabled' = true: stage 2 needs at least one [[sink]] "
                                  "(add a [[sink]] or set [stage2] enabled = false)");
    }
}

Scenario parseScenarioString(std::string_view text, const std::string& sourceName) {
    if (deepestDottedKey(text) > 32)
        throw InputError(sourceName + ": a dotted key or table name of more than 32 parts; cavesim's keys have at "
                                      "most 3 (e.g. rock.noise.scale)");
    toml::table root;
    try {
        root = toml::parse(text, sourceName);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << sourceName << ":" << e.source().begin.line << ": malformed TOML: " << e.description();
        throw InputError(os.str());
    }
    return parseTable(root, sourceName);
}

Scenario parseScenarioFile(const std::string& path) {
    // Check what the path is before opening it: a directory reads as an empty file, a FIFO blocks
    // and /dev/zero never ends.
    std::error_code ec;
    const auto st = std::filesystem::status(path, ec);
    if (ec || !std::filesystem::exists(st))
        throw InputError(path + ": cannot open the scenario file (missing or unreadable)");
    if (std::filesystem::is_directory(st)) throw InputError(path + ": is a directory, not a scenario file");
    if (!std::filesystem::is_regular_file(st))
        throw InputError(path + ": not a regular file (a scenario is a TOML text file)");
    constexpr std::uintmax_t kMaxBytes = 16u << 20;
    const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (!ec && bytes > kMaxBytes)
        throw InputError(path + ": " + std::to_string(bytes) + " bytes; a scenario file may have at most 16 MiB");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open the scenario file (missing or unreadable)");
    std::ostringstream buf;
    buf << in.rdbuf();
    return parseScenarioString(buf.str(), path);
}

std::string choiceName(ProtosinkMode v) { return nameOf(kProtosinkNames, v); }
std::string choiceName(ZoneSpeed v) { return nameOf(kZoneSpeedNames, v); }
std::string choiceName(TransportWeight v) { return nameOf(kWeightNames, v); }

std::string scenarioKey(const Scenario& s, const void* field) {
    if (field == &s.stage1.maxGraphVoxels) return "stage1.max_graph_voxels";
    throw RuntimeError("scenarioKey: not a registered field");
}

Scenario defaultScenario() { return parseScenarioString(kDefaultScenarioToml, "<built-in fig10>"); }

namespace {

toml::array arr3(const Vec3d& v) { return toml::array{v[0], v[1], v[2]}; }
toml::array iarr3(const std::array<int, 3>& v) { return toml::array{v[0], v[1], v[2]}; }

toml::table boxTable(const VoxelBox& b) {
    toml::table t;
    if (b.lo == b.hi) t.insert("at", iarr3(b.lo));
    else t.insert("box", toml::array{iarr3(b.lo), iarr3(b.hi)});
    return t;
}

}  // namespace

std::string scenarioToToml(const Scenario& s) {
    toml::table root;
    root.insert("name", s.name);
    root.insert("seed", static_cast<std::int64_t>(s.seed));
    root.insert("domain", toml::table{{"size", iarr3(s.size)}, {"voxel_size", s.voxelSize}});

    toml::table rock{{"porosity", s.rockPorosity},
                     {"noise", toml::table{{"amplitude", s.noise.amplitude},
                                           {"scale", s.noise.scale},
                                           {"octaves", s.noise.octaves}}}};
    if (!s.spheres.empty()) {
        toml::array a;
        for (const auto& o : s.spheres)
            a.push_back(toml::table{{"center", arr3(o.center)}, {"radius", o.radius}, {"core_porosity", o.corePorosity}});
        rock.insert("sphere", a);
    }
    if (!s.planes.empty()) {
        toml::array a;
        for (const auto& p : s.planes)
            a.push_back(toml::table{{"point", arr3(p.point)},
                                    {"normal", arr3(p.normal)},
                                    {"thickness", p.thickness},
                                    {"porosity", p.porosity},
                                    {"extent", p.extent},
                                    {"kind", nameOf(kPlaneKindNames, p.kind)}});
        rock.insert("plane", a);
    }
    if (!s.channels.empty()) {
        toml::array a;
        for (const auto& c : s.channels) {
            toml::array pts;
            for (const auto& p : c.points) pts.push_back(arr3(p));
            a.push_back(toml::table{{"points", pts},
                                    {"radius", c.radius},
                                    {"porosity", c.porosity},
                                    {"protochannel", c.protochannel}});
        }
        rock.insert("channel", a);
    }
    root.insert("rock", rock);

    toml::array sources;
    for (const auto& src : s.sources) {
        toml::table t = boxTable(src.box);
        t.insert("pressure", src.pressure);
        sources.push_back(t);
    }
    if (!sources.empty()) root.insert("source", sources);
    toml::array sinks;
    for (const auto& snk : s.sinks) sinks.push_back(boxTable(snk.box));
    if (!sinks.empty()) root.insert("sink", sinks);

    const Stage1Options& g1 = s.stage1;
    toml::array aim;
    for (const auto& p : g1.aim) aim.push_back(arr3(p));
    toml::array faces;
    for (const GridFace f : g1.boundaryFaces) faces.push_back(nameOf(kFaceNames, f));
    root.insert("stage1", toml::table{{"enabled", g1.enabled},
                                      {"protosinks", nameOf(kProtosinkNames, g1.protosinks)},
                                      {"clusters", g1.clusters},
                                      {"cluster_radius", g1.clusterRadius},
                                      {"aim", aim},
                                      {"permeability", nameOf(kZoneSpeedNames, g1.permeability)},
                                      {"protochannel_porosity", g1.protochannelPorosity},
                                      {"capacity_exponent", g1.capacityExponent},
                                      {"max_graph_voxels", static_cast<std::int64_t>(g1.maxGraphVoxels)},
                                      {"boundary_faces", faces},
                                      {"protosink_share", g1.protosinkShare},
                                      {"branch_flow", g1.branchFlow},
                                      {"resistance_noise", g1.resistanceNoise}});
    const Stage2Options& g2 = s.stage2;
    toml::array snaps;
    for (int it : g2.snapshots) snaps.push_back(it);
    root.insert("stage2", toml::table{{"enabled", g2.enabled},
                                      {"iterations", g2.iterations},
                                      {"p_rate", g2.pRate},
                                      {"p_rate_channel", g2.pRateChannel},
                                      {"w0", g2.w0},
                                      {"wa", g2.wa},
                                      {"m", g2.m},
                                      {"pressure_scale", g2.pressureScale},
                                      {"channel_threshold", g2.channelThreshold},
                                      {"protochannel_porosity", g2.protochannelPorosity},
                                      {"source_porosity", g2.sourcePorosity},
                                      {"weight", nameOf(kWeightNames, g2.weight)},
                                      {"blending", nameOf(kBlendingNames, g2.blending)},
                                      {"snapshots", snaps}});
    root.insert("output", toml::table{{"mesh_style", nameOf(kMeshStyleNames, s.output.meshStyle)},
                                      {"image_width", s.output.imageWidth},
                                      {"images", s.output.images},
                                      {"mesh", s.output.mesh},
                                      {"cave", nameOf(kCaveNames, s.output.cave)}});
    std::ostringstream os;
    os << "# Effective scenario: every key with its value, defaults filled in.\n" << root << "\n";
    return os.str();
}

}  // namespace cavesim
