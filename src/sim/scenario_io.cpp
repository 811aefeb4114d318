#include "sim/scenario_io.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include <toml++/toml.h>

#include "core/check.h"
#include "core/error.h"
#include "core/text.h"
#include "sim/default_scenario.h"
#include "sim/parameters.h"
#include "sim/recharge.h"
#include "sim/scenario_toml.h"

namespace cavesim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();


void describeInto(const toml::node& n, std::string& out) {
    if (n.is_string()) {
        out += quoted(n.as_string()->get());
    } else if (n.is_floating_point()) {
        // A float is shown as one (4.0, not 4), so "must be a whole number" does not quote a
        // value that looks whole.
        std::string t = shortestText(n.as_floating_point()->get());
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

/// What a pass over the text outside strings and comments finds before toml++ sees it.
struct TextScan {
    int deepestDottedKey = 0;                         ///< longest run of dotted key parts (`a.b.c` is 3)
    std::size_t nonAsciiAt = std::string_view::npos;  ///< offset of the first byte >= 0x80, if any
};

/// toml++ 3.3 recurses once per dotted key part and overflows the stack on keys of ~100 000 parts
/// (cavesim's keys have 3); and it reaches code it marks unreachable on a non-ASCII character where
/// a key is expected (`é = 1`). Outside strings and comments a scenario needs neither.
TextScan scanOutsideStrings(std::string_view t) {
    TextScan scan;
    int dots = 0;
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
        } else if (static_cast<unsigned char>(ch) >= 0x80) {
            if (scan.nonAsciiAt == std::string_view::npos) scan.nonAsciiAt = c;
            dots = 0;
        } else if (ch == '.') {
            scan.deepestDottedKey = std::max(scan.deepestDottedKey, ++dots + 1);
        } else if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-' || ch == ' ' ||
                     ch == '\t')) {
            dots = 0;
        }
    }
    return scan;
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

    double toNumber(const std::string& key, const toml::node& n, double lo, double hi, bool loOpen, bool hiOpen) const {
        double v = 0;
        if (auto i = n.as_integer())
            v = double(i->get());
        else if (auto f = n.as_floating_point())
            v = f->get();
        else
            fail(key, &n, "must be a number " + range(lo, hi, loOpen, hiOpen));
        const bool ok = std::isfinite(v) && (loOpen ? v > lo : v >= lo) && (hiOpen ? v < hi : v <= hi);
        if (!ok) fail(key, &n, "must be a number " + range(lo, hi, loOpen, hiOpen));
        return v;
    }

    long toInteger(const std::string& key, const toml::node& n, long lo, long hi) const {
        auto i = n.as_integer();
        const std::string allowed =
            "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
        if (!i) fail(key, &n, allowed);
        const long v = long(i->get());
        if (v < lo || v > hi) fail(key, &n, allowed);
        return v;
    }

    Vec3d toVec3(const std::string& key, const toml::node& n, double lo, double hi) const {
        auto a = n.as_array();
        const std::string allowed = "must be an array of 3 numbers, each " + range(lo, hi, false, false);
        if (!a || a->size() != 3) fail(key, &n, allowed);
        Vec3d v{};
        for (std::size_t c = 0; c < 3; ++c) {
            const toml::node& e = *a->get(c);
            if (e.as_integer())
                v[c] = double(e.as_integer()->get());
            else if (e.as_floating_point())
                v[c] = e.as_floating_point()->get();
            else
                fail(key, &n, allowed);
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
            fail(key, nullptr,
                 "at most " + std::to_string(maxEntries) + " [[" + qualified(key) + "]] entries, found " +
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

/// The registry entry of the field `pick` selects in a scenario with one entry in every table of
/// arrays: the parser's cross-key rules find their keys through it.
template <typename F>
std::pair<const ParamSection*, const Param*> probeParam(F pick) {
    static Scenario probe = [] {
        Scenario p;
        p.spheres.resize(1);
        p.planes.resize(1);
        p.channels.resize(1);
        p.inceptionHorizons.resize(1);
        p.fractureFamilies.resize(1);
        p.sources.resize(1);
        p.sinks.resize(1);
        p.recharge.resize(1);
        p.stage2.phases.resize(1);
        return p;
    }();
    return findParam(probe, pick(probe));
}

/// The registry entry of the field `pick` selects in a scenario with one entry in every table of
/// arrays: cross-key rules and messages find their keys through it.
template <typename F>
const Param& entryOf(F pick) {
    return *probeParam(pick).second;
}

/// The section holding the field `pick` selects.
template <typename F>
const ParamSection& sectionOf(F pick) {
    return *probeParam(pick).first;
}

struct ParseContext {
    Scenario& s;
    const std::string& file;
    std::size_t channelPoints = 0;  // all polylines together: the effective scenario rewrites each
    std::size_t entry = 0;          // index of the table-of-arrays entry being read (keyLines)
};

/// The `Scenario::keyLines` name of `key` of `section`: entries of a table of arrays carry their index.
std::string lineKey(const ParamSection& section, const std::string& key, std::size_t entry) {
    return section.qualified(key) + (section.isArray ? "[" + std::to_string(entry) + "]" : std::string());
}

/// The `box` entry of a source or sink section (the one after `at`).
const Param& boxEntry(const ParamSection& section) {
    return *std::find_if(section.params.begin(), section.params.end(),
                         [](const Param& q) { return q.type == ParamType::kVoxelBox; });
}

/// `at` or `box` of a source or sink (entries `at`, then `box`, of `section`).
VoxelBox readBox(TableReader& r, const ParamSection& section, const Param& atParam, const std::array<int, 3>& size) {
    const Param& boxParam = boxEntry(section);
    const std::string& atKey = atParam.key;
    const std::string& boxKey = boxParam.key;
    const std::string& what = section.path;
    const toml::node* at = r.get(atKey);
    const toml::node* box = r.get(boxKey);
    if (at && box) r.fail(boxKey, box, "give either '" + atKey + "' or '" + boxKey + "', not both");
    if (!at && !box)
        r.fail(atKey, nullptr,
               "a " + what + " needs '" + atKey + " = [x, y, z]' or '" + boxKey + " = [[x0, y0, z0], [x1, y1, z1]]'");
    const long lo = long(atParam.range.lo), hi = long(atParam.range.hi);
    VoxelBox b;
    if (at) {
        b.lo = r.ivec3(atKey, *at, lo, hi);
        b.hi = b.lo;
    } else {
        auto a = box->as_array();
        if (!a || a->size() != 2) r.fail(boxKey, box, "must be [[x0, y0, z0], [x1, y1, z1]] (inclusive voxel indices)");
        b.lo = r.ivec3(boxKey, *a->get(0), lo, hi);
        b.hi = r.ivec3(boxKey, *a->get(1), lo, hi);
    }
    for (int c = 0; c < 3; ++c) {
        const toml::node* n = at ? at : box;
        const std::string& key = at ? atKey : boxKey;
        if (b.lo[c] > b.hi[c]) r.fail(key, n, "box corners must satisfy x0 <= x1, y0 <= y1, z0 <= z1");
        if (b.lo[c] < 0 || b.hi[c] >= size[c]) {
            r.fail(key, n,
                   "the " + what + " must lie inside the domain: indices 0.." + std::to_string(size[0] - 1) + ", 0.." +
                       std::to_string(size[1] - 1) + ", 0.." + std::to_string(size[2] - 1));
        }
    }
    return b;
}

long longBound(double v) {
    return v >= double(std::numeric_limits<long>::max()) ? std::numeric_limits<long>::max() : long(v);
}

void readValue(TableReader& r, const ParamSection& section, const Param& p, const toml::node& node, void* record,
               ParseContext& ctx);

/// Reads entry `p` of `section` from `r` into `record`; absent keys keep the record's default.
void readParam(TableReader& r, const ParamSection& section, const Param& p, void* record, ParseContext& ctx) {
    if (p.type == ParamType::kVoxelBox) return;  // read with `at`
    if (p.type == ParamType::kVoxel) {
        const VoxelBox b = readBox(r, section, p, ctx.s.size);
        std::vector<std::int64_t> corners(b.lo.begin(), b.lo.end());
        if (b.lo == b.hi) return p.set(record, corners);
        corners.insert(corners.end(), b.hi.begin(), b.hi.end());
        boxEntry(section).set(record, corners);
        return;
    }
    const std::string& key = p.key;
    const toml::node* n = r.get(key);
    if (!n && p.required) r.fail(key, nullptr, "is required: " + p.shapeText);
    if (n) ctx.s.keyLines[lineKey(section, key, ctx.entry)] = int(n->source().begin.line);
    if (n) readValue(r, section, p, *n, record, ctx);
    const Param& pRateChannel = entryOf([](Scenario& s) { return &s.stage2.pRateChannel; });
    if (&p == &pRateChannel) {
        const Param& pRate = entryOf([](Scenario& s) { return &s.stage2.pRate; });
        const Stage2Options& g2 = ctx.s.stage2;
        if (g2.pRateChannel > g2.pRate) {
            // Blame the key the file gives; if it gives only p_rate, the default channel rate is the bound.
            if (n)
                r.fail(key, n,
                       "must not exceed " + pRate.key + " (" + shortestText(g2.pRate) +
                           "): channels resist flow less than rock");
            r.fail(pRate.key, r.get(pRate.key),
                   "must be at least " + key + " (" + shortestText(g2.pRateChannel) +
                       ", the default): channels resist flow less than rock; lower " + key + " too");
        }
    }
}

/// Converts and checks node `n` of entry `p` and sets it in `record`.
void readValue(TableReader& r, const ParamSection& section, const Param& p, const toml::node& node, void* record,
               ParseContext& ctx) {
    const std::string& key = p.key;
    const toml::node* n = &node;
    const ParamRange& g = p.range;
    const double scale = g.domainScaled ? std::max({ctx.s.size[0], ctx.s.size[1], ctx.s.size[2]}) * 4.0 : 1.0;
    const double lo = g.lo * scale, hi = g.hi * scale;
    switch (p.type) {
        case ParamType::kBool: {
            auto b = n->as_boolean();
            if (!b) r.fail(key, n, "must be true or false");
            p.set(record, b->get());
            break;
        }
        case ParamType::kInt:
            p.set(record, std::int64_t(r.toInteger(key, *n, longBound(lo), longBound(hi))));
            break;
        case ParamType::kReal:
            p.set(record, r.toNumber(key, *n, lo, hi, g.loOpen, g.hiOpen));
            break;
        case ParamType::kString: {
            auto str = n->as_string();
            const std::string allowed = "must be " + p.shapeText;
            if (!str || str->get().empty() || str->get().size() > 64) r.fail(key, n, allowed);
            for (char c : str->get())
                if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_')) r.fail(key, n, allowed);
            p.set(record, str->get());
            break;
        }
        case ParamType::kPath: {
            auto str = n->as_string();
            const std::string allowed = "must be " + p.shapeText;
            if (!str || str->get().size() > 4096) r.fail(key, n, allowed);
            for (char c : str->get())
                if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) r.fail(key, n, allowed);
            p.set(record, str->get());
            break;
        }
        case ParamType::kChoice: {
            std::string list;
            for (const auto& a : p.choices) list += (list.empty() ? "\"" : ", \"") + std::string(a.name) + "\"";
            auto str = n->as_string();
            if (!str) r.fail(key, n, "must be one of " + list);
            const auto it = std::find_if(p.choices.begin(), p.choices.end(),
                                         [&](const ParamChoice& c) { return str->get() == c.name; });
            if (it == p.choices.end()) r.fail(key, n, "must be one of " + list);
            p.set(record, str->get());
            break;
        }
        case ParamType::kInt3: {
            const auto v = r.ivec3(key, *n, longBound(lo), longBound(hi));
            p.set(record, std::vector<std::int64_t>(v.begin(), v.end()));
            break;
        }
        case ParamType::kReal3: {
            const Vec3d v = r.toVec3(key, *n, lo, hi);
            p.set(record, std::vector<double>(v.begin(), v.end()));
            if (p.nonZero && std::hypot(v[0], v[1], v[2]) < 1e-9) r.fail(key, n, "must not be zero");
            break;
        }
        case ParamType::kReal3List: {
            auto a = n->as_array();
            if (!a || a->size() < p.minItems) r.fail(key, n, "must be " + p.shapeText);
            if (p.maxItems > 0 && a->size() > p.maxItems)
                r.fail(key, n, "must have at most " + std::to_string(p.maxItems) + " points");
            if (&p == &entryOf([](Scenario& s) { return &s.channels[0].points; })) {
                ctx.channelPoints += a->size();
                if (ctx.channelPoints > 65536)
                    r.fail(key, n, "all " + section.header() + " polylines together may have at most 65536 points");
            }
            std::vector<Vec3d> v;
            for (const toml::node& e : *a) v.push_back(r.toVec3(key, e, lo, hi));
            p.set(record, v);
            break;
        }
        case ParamType::kChoiceList: {
            const std::string allowed = "must be " + p.shapeText;
            auto a = n->as_array();
            if (!a) r.fail(key, n, allowed);
            std::vector<std::string> v;
            for (const toml::node& e : *a) {
                auto str = e.as_string();
                if (!str) r.fail(key, n, allowed);
                const bool known = std::any_of(p.choices.begin(), p.choices.end(),
                                               [&](const ParamChoice& c) { return str->get() == c.name; });
                if (!known || std::find(v.begin(), v.end(), str->get()) != v.end()) r.fail(key, n, allowed);
                v.push_back(str->get());
            }
            p.set(record, v);
            break;
        }
        case ParamType::kIntList: {
            auto a = n->as_array();
            if (!a) r.fail(key, n, "must be " + p.shapeText);
            if (p.maxItems > 0 && a->size() > p.maxItems)
                r.fail(key, n, "must list at most " + std::to_string(p.maxItems) + " " + p.unit);
            std::vector<std::int64_t> v;
            for (const toml::node& e : *a) v.push_back(r.toInteger(key, e, longBound(lo), longBound(hi)));
            p.set(record, v);
            break;
        }
        case ParamType::kVoxel:
        case ParamType::kVoxelBox:
            break;
    }
}

/// Reads `table` as `section` into `record`, then its child sections, then rejects unknown keys.
void readSection(const ParamSection& section, const toml::table& table, TableReader& r, void* record,
                 ParseContext& ctx) {
    std::vector<std::string> known;
    for (const Param& p : section.params) {
        readParam(r, section, p, record, ctx);
        known.push_back(p.key);
    }
    // A key given where it does not apply (a sinkholes-only key on a stream) would be ignored.
    for (const Param& p : section.params)
        if (p.applies && !p.applies(record))
            if (const toml::node* n = table.get(p.key)) r.fail(p.key, n, p.notApplicable);
    for (const ParamSection& child : scenarioParameters()) {
        const std::string prefix = section.path.empty() ? "" : section.path + ".";
        if (child.path.empty() || child.path.compare(0, prefix.size(), prefix) != 0 ||
            child.path.find('.', prefix.size()) != std::string::npos)
            continue;
        const std::string key = child.path.substr(prefix.size());
        known.push_back(key);
        if (child.isArray) {
            const std::size_t limit =
                child.limitReason.empty() ? child.maxEntries : std::numeric_limits<std::size_t>::max();
            std::size_t entries = 0;
            const std::vector<const toml::table*> tables = r.tableArray(key, limit);
            if (child.nonEmpty && tables.empty())
                if (const toml::node* n = table.get(key))
                    throw InputError(ctx.file + ":" + std::to_string(n->source().begin.line) + ": key '" + child.path +
                                     "' = []: an empty list; give at least one " + child.header() +
                                     " entry, or leave the key out");
            for (const toml::table* t : tables) {
                if (!child.limitReason.empty() && entries == child.maxEntries)
                    throw InputError(ctx.file + ":" + std::to_string(t->source().begin.line) + ": key '" + child.path +
                                     "': at most " + std::to_string(child.maxEntries) + " " + child.header() +
                                     " entries (" + child.limitReason + ")");
                ++entries;
                TableReader er(*t, child.path, ctx.file);
                void* rec = child.append(ctx.s);
                if (child.setLine) child.setLine(rec, int(t->source().begin.line));
                const std::size_t outer = ctx.entry;
                ctx.entry = entries - 1;
                readSection(child, *t, er, rec, ctx);
                ctx.entry = outer;
            }
        } else if (const toml::table* t = r.subtable(key)) {
            TableReader cr(*t, child.path, ctx.file);
            if (child.setLine) child.setLine(child.mutableRecord(ctx.s, 0), int(t->source().begin.line));
            readSection(child, *t, cr, child.mutableRecord(ctx.s, 0), ctx);
        }
    }
    r.finish(known);
}

std::string where(const Scenario& s, int line) {
    return s.path + (line > 0 ? ":" + std::to_string(line) : std::string());
}

/// A snapshot the run never reaches (0, or after its last iteration) would silently give no picture.
void checkSnapshots(const Scenario& s, int line) {
    const std::vector<int>& snaps = s.stage2.snapshots;
    if (!snaps.empty()) {
        // A snapshot is only a picture: without pictures or without stage 2 it would give nothing.
        std::string list;
        for (int it : snaps) list += (list.empty() ? "" : ", ") + std::to_string(it);
        const std::string head = where(s, line) + ": key '" + scenarioKey(s, &s.stage2.snapshots) + "' = [" + list +
                                 "]: a snapshot is a picture of the state (images/iter_NNNN.png, images/sequence.png)";
        if (!s.output.images)
            throw InputError(head + " and '" + scenarioKey(s, &s.output.images) +
                             "' = false writes no pictures: remove the snapshots or set images = true");
        if (!s.stage2.enabled) {
            const std::string enabled = scenarioKey(s, &s.stage2.enabled);
            throw InputError(head + " taken in stage 2, and '" + enabled +
                             "' = false: remove the snapshots or enable stage 2");
        }
    }
    if (!s.stage2.enabled) return;
    const long total = s.stage2.totalIterations();
    for (int it : s.stage2.snapshots)
        if (it < 1 || it > total)
            throw InputError(
                where(s, line) + ": key '" + scenarioKey(s, &s.stage2.snapshots) + "' = " + std::to_string(it) +
                ": a snapshot is taken after one of the run's stage-2 iterations, 1 to " + std::to_string(total) +
                (s.stage2.phases.empty() ? std::string() : " (the [[phase]] iterations together)"));
}

/// `[hydrology]` and `[[phase]]` keys the run would ignore: a phase, or a `[hydrology]` key away from
/// its default, with stage 2 off; the table's shape keys (dip, its direction, the vadose drift) away
/// from their defaults when no water table is set anywhere. Only keys the file gives are refused, and
/// a key at its default changes nothing (the example scenario lists every key at its default).
void checkStage2Tables(const toml::table& root, const Scenario& s) {
    const Hydrology& h = s.stage2.hydrology;
    const ParamSection& hydro = sectionOf([](Scenario& p) { return &p.stage2.hydrology.dip; });
    const ParamSection& phase = sectionOf([](Scenario& p) { return &p.stage2.phases[0].iterations; });
    const toml::node* hydroNode = root.get(hydro.path);
    const toml::table* t = hydroNode ? hydroNode->as_table() : nullptr;
    // The first key of [hydrology] the file gives with a value other than its default, among `fields`.
    const auto firstChanged = [&](std::initializer_list<const void*> fields) -> const Param* {
        if (!t) return nullptr;
        for (const void* field : fields) {
            const Param* p = findParam(s, field).second;
            if (t->get(p->key) && p->get(&h) != p->get(hydro.defaults())) return p;
        }
        return nullptr;
    };
    const auto refuse = [&](const Param& p, const std::string& why) {
        TableReader r(*t, hydro.path, s.path);
        r.fail(p.key, t->get(p.key), why);
    };
    if (!s.stage2.enabled) {
        const auto [stage2, enabled] = findParam(s, &s.stage2.enabled);
        const std::string off = stage2->qualified(enabled->key) + " = false";
        if (const Param* p = firstChanged({&h.waterTable, &h.dip, &h.dipDirection, &h.lateral, &h.fromSite}))
            refuse(*p,
                   "the water table acts on stage 2, which is off (" + off + "); leave the key out or enable stage 2");
        if (!s.stage2.phases.empty())
            throw InputError(where(s, s.stage2.phases[0].line) + ": table " + phase.header() +
                             ": base-level phases are stage-2 iterations, and stage 2 is off (" + off +
                             "); remove the phases or enable stage 2");
        return;
    }
    const bool phaseTable = std::any_of(s.stage2.phases.begin(), s.stage2.phases.end(),
                                        [](const Stage2Phase& ph) { return ph.waterTable >= 0; });
    if (h.waterTable >= 0 || h.fromSite || phaseTable) return;
    if (const Param* p = firstChanged({&h.dip, &h.dipDirection, &h.lateral}))
        refuse(*p, "shapes the water table, and there is none: set '" + scenarioKey(s, &h.waterTable) + "', '" +
                       scenarioKey(s, &h.fromSite) + "' = true or a " + phase.header() + " '" +
                       phase.qualified(entryOf([](Scenario& p) { return &p.stage2.phases[0].waterTable; }).key) +
                       "', or leave the key out");
}

}  // namespace

/// The most speleothem steps a `time_step` may ask for.
constexpr double kMaxSpeleothemSteps = 1e6;

Scenario parseScenarioTable(const toml::table& root, const std::string& sourceName) {
    Scenario s;
    s.path = sourceName;
    TableReader top(root, "", sourceName);
    ParseContext ctx{s, sourceName};
    const ParamSection& topSection = scenarioParameters().front();
    readSection(topSection, root, top, &s, ctx);
    checkStage2Tables(root, s);
    // Growth frames are pictures: given without pictures they would give nothing (the default is
    // not refused: it is simply not drawn).
    const SpeleothemOptions& sp = s.speleothems;
    if (sp.enabled && !s.output.images && sp.frames > 0 && keyLine(s, &sp.frames) > 0)
        throw InputError(where(s, keyLine(s, &sp.frames)) + ": key '" + scenarioKey(s, &sp.frames) +
                         "' = " + std::to_string(sp.frames) + ": growth frames are pictures, and '" +
                         scenarioKey(s, &s.output.images) +
                         "' = false writes none: leave the key out (or 0) or set images = true");
    checkSnapshots(s, keyLine(s, &s.stage2.snapshots));
    validateScenario(s);
    return s;
}

namespace {

/// The line of the key holding `field`, or `fallback` (its table's line) when it was not written.
int keyLineOr(const Scenario& s, const void* field, int fallback) {
    const int line = keyLine(s, field);
    return line > 0 ? line : fallback;
}

/// The water tables and the phases' terminals (docs/model.md, "Water table and gravity").
void validateHydrology(const Scenario& s) {
    const int nz = s.size[2];
    const auto checkLevel = [&](double level, const void* field, int line, const std::string& entry) {
        if (level == -1.0 || (level >= 0 && level <= nz - 1)) return;
        std::ostringstream os;
        os << where(s, keyLineOr(s, field, line)) << ": key '" << scenarioKey(s, field) << "'" << entry << " = " << shortestText(level)
           << ": a water table must lie in the block, 0 to nz - 1 = " << nz - 1
           << " (voxel index units), or be -1 for none";
        throw InputError(os.str());
    };
    const Hydrology& h = s.stage2.hydrology;
    checkLevel(h.waterTable, &h.waterTable, h.line, "");
    if (h.fromSite && s.site.waterTable.empty())
        throw InputError(where(s, keyLineOr(s, &h.fromSite, h.line)) + ": key '" + scenarioKey(s, &h.fromSite) +
                         "' = true needs a surface in '" +
                         scenarioKey(s, &s.site.waterTable) + "'");
    if (h.fromSite && (h.waterTable != -1.0 || h.dip != 0.0))
        throw InputError(where(s, keyLineOr(s, &h.fromSite, h.line)) + ": key '" + scenarioKey(s, &h.fromSite) +
                         "' = true takes the table from the site: "
                         "leave '" +
                         scenarioKey(s, &h.waterTable) + "' at -1 and '" + scenarioKey(s, &h.dip) + "' at 0");
    const auto& phases = s.stage2.phases;
    for (std::size_t n = 0; n < phases.size(); ++n) {
        const Stage2Phase& ph = phases[n];
        const std::string entry = " (entry " + std::to_string(n + 1) + ")";
        checkLevel(ph.waterTable, &ph.waterTable, ph.line, entry);
    }
    // A site's sinkholes and springs are numbered too: checked when the site is read.
    const bool siteTerminals = !s.site.sinkholes.empty() || !s.site.springs.empty();
    if (!siteTerminals || s.siteData) validatePhaseTerminals(s);
}

}  // namespace

void validatePhaseTerminals(const Scenario& s) {
    if (s.stage2.phases.empty()) return;
    const std::size_t given = s.sources.size(), recharge = rechargeSources(s).size();
    const std::size_t siteSources = s.siteData ? s.siteData->sources.size() : 0;
    const std::size_t siteSinks = s.siteData ? s.siteData->sinks.size() : 0;
    const std::size_t sources = given + recharge + siteSources, sinks = s.sinks.size() + siteSinks;
    for (std::size_t n = 0; n < s.stage2.phases.size(); ++n) {
        const Stage2Phase& ph = s.stage2.phases[n];
        const auto check = [&](const std::vector<int>& list, const void* field, std::size_t count, const char* what,
                               const std::string& numbering) {
            for (int x : list)
                if (x < 1 || std::size_t(x) > count) {
                    std::ostringstream os;
                    os << where(s, keyLineOr(s, field, ph.line)) << ": key '" << scenarioKey(s, field) << "' (entry "
                       << n + 1 << ") names "
                       << what << " " << x << ": the run has " << count << " " << what << "s, numbered 1 to " << count
                       << " (" << numbering << ")";
                    throw InputError(os.str());
                }
        };
        check(ph.sinks, &ph.sinks, sinks, "sink",
              std::to_string(s.sinks.size()) + " [[sink]] entries in file order, then " + std::to_string(siteSinks) +
                  " [site] springs");
        check(ph.sources, &ph.sources, sources, "source",
              std::to_string(given) + " [[source]] entries in file order, then " + std::to_string(recharge) +
                  " [[recharge]] inputs, then " + std::to_string(siteSources) + " [site] sinkholes");
    }
}

bool boxesOverlap(const VoxelBox& a, const VoxelBox& b) {
    for (int c = 0; c < 3; ++c)
        if (a.hi[c] < b.lo[c] || b.hi[c] < a.lo[c]) return false;
    return true;
}

void validateScenario(const Scenario& s) {
    // Checks the reader makes across keys, again for a scenario changed after reading (an ensemble's
    // --vary): p_rate_channel at most p_rate, snapshots the run reaches, speleothem steps.
    if (s.stage2.pRateChannel > s.stage2.pRate)
        throw InputError(s.path + ": key '" + scenarioKey(s, &s.stage2.pRateChannel) + "' = " +
                         shortestText(s.stage2.pRateChannel) + ": must not exceed " + scenarioKey(s, &s.stage2.pRate) +
                         " (" + shortestText(s.stage2.pRate) + "): channels resist flow less than rock");
    checkSnapshots(s, 0);
    // A step far below the stable one only multiplies the steps (each a walk over the level set):
    // more than a million is refused rather than run for days.
    const SpeleothemOptions& sp = s.speleothems;
    if (sp.enabled && sp.timeStep > 0 && sp.years / sp.timeStep > kMaxSpeleothemSteps) {
        std::ostringstream os;
        os << where(s, keyLine(s, &sp.timeStep)) << ": key '" << scenarioKey(s, &sp.timeStep)
           << "' = " << shortestText(sp.timeStep) << ": " << shortestText(sp.years) << " years in steps of "
           << shortestText(sp.timeStep) << " years would take " << shortestText(std::ceil(sp.years / sp.timeStep))
           << " steps, more than " << long(kMaxSpeleothemSteps) << "; use a step of at least "
           << shortestText(sp.years / kMaxSpeleothemSteps) << " years, or 0 (the stable step)";
        throw InputError(os.str());
    }
    const ParamSection& source = sectionOf([](Scenario& p) { return &p.sources[0].box; });
    const ParamSection& sink = sectionOf([](Scenario& p) { return &p.sinks[0].box; });
    const auto checkInside = [&](const ParamSection& section, const VoxelBox& box, int line, std::size_t i) {
        for (int c = 0; c < 3; ++c)
            if (box.lo[c] < 0 || box.hi[c] >= s.size[c])
                throw InputError(where(s, line) + ": " + section.header() + " " + std::to_string(i + 1) +
                                 " lies outside the domain");
    };
    for (std::size_t i = 0; i < s.sources.size(); ++i) {
        checkInside(source, s.sources[i].box, s.sources[i].line, i);
        for (std::size_t j = 0; j < s.sinks.size(); ++j) {
            if (boxesOverlap(s.sources[i].box, s.sinks[j].box)) {
                throw InputError(where(s, s.sinks[j].line) + ": key '" + sink.path + "' (entry " +
                                 std::to_string(j + 1) + ") overlaps " + source.header() + " entry " +
                                 std::to_string(i + 1) + " (line " + std::to_string(s.sources[i].line) +
                                 "): a voxel cannot be both source and sink");
            }
        }
    }
    for (std::size_t j = 0; j < s.sinks.size(); ++j) checkInside(sink, s.sinks[j].box, s.sinks[j].line, j);
    // Stage 1 keeps `sink_gap` voxels of rock around every sink; an aim point there would draw the
    // protochannels onto the sink.
    if (s.stage1.enabled) {
        for (std::size_t a = 0; a < s.stage1.aim.size(); ++a)
            for (std::size_t j = 0; j < s.sinks.size(); ++j) {
                const Vec3d& p = s.stage1.aim[a];
                double dist = 0;  // Chebyshev distance from the point to the sink box, voxels
                for (int c = 0; c < 3; ++c)
                    dist = std::max({dist, double(s.sinks[j].box.lo[c]) - p[c], p[c] - double(s.sinks[j].box.hi[c])});
                if (dist > s.stage1.sinkGap) continue;
                std::ostringstream os;
                os << s.path << ": key '" << scenarioKey(s, &s.stage1.aim) << "' point " << a + 1 << " = ["
                   << shortestText(p[0]) << ", " << shortestText(p[1]) << ", " << shortestText(p[2]) << "] lies "
                   << (dist <= 0 ? std::string("inside") : "within " + std::to_string(s.stage1.sinkGap) + " voxels of")
                   << " " << sink.header() << " entry " << j + 1 << " (line " << s.sinks[j].line
                   << "): an aim point must be more than '" << scenarioKey(s, &s.stage1.sinkGap)
                   << "' = " << s.stage1.sinkGap
                   << " voxels from every sink (the largest of |dx|, |dy|, |dz| to the sink box), because stage 1 "
                      "keeps that much rock between protochannels and sinks";
                throw InputError(os.str());
            }
    }
    validateFractureFamilies(s);
    validateRecharge(s);
    validateHydrology(s);
    // Sinkholes and springs of a [site] are sources and sinks too (read later, by the site module).
    if ((s.stage1.enabled || s.stage2.enabled) && s.sources.empty() && s.recharge.empty() && s.site.sinkholes.empty()) {
        throw InputError(s.path + ": key '" + source.path + "': at least one " + source.header() +
                         " is needed when a stage is enabled");
    }
    if (s.stage2.enabled && s.sinks.empty() && s.site.springs.empty()) {
        const auto [stage2, enabled] = findParam(s, &s.stage2.enabled);
        throw InputError(s.path + ": key '" + stage2->qualified(enabled->key) +
                         "' = true: stage 2 needs at least one " + sink.header() + " (add a " + sink.header() +
                         " or set " + stage2->header() + " " + enabled->key + " = false)");
    }
}

Scenario parseScenarioString(std::string_view text, const std::string& sourceName) {
    const TextScan scan = scanOutsideStrings(text);
    if (scan.nonAsciiAt != std::string_view::npos) {
        const auto line = 1 + std::count(text.begin(), text.begin() + std::ptrdiff_t(scan.nonAsciiAt), '\n');
        throw InputError(sourceName + ":" + std::to_string(line) +
                         ": a non-ASCII character outside a string or comment; keys are ASCII letters, digits, "
                         "'_' and '-', and other text belongs in quotes");
    }
    if (scan.deepestDottedKey > 32) {
        const Scenario d;
        throw InputError(sourceName +
                         ": a dotted key or table name of more than 32 parts; cavesim's keys have at most 3 (e.g. " +
                         scenarioKey(d, &d.noise.scale) + ")");
    }
    toml::table root;
    try {
        root = toml::parse(text, sourceName);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << sourceName << ":" << e.source().begin.line << ": malformed TOML: " << e.description();
        throw InputError(os.str());
    }
    return parseScenarioTable(root, sourceName);
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

std::string scenarioKey(const Scenario& s, const void* field) {
    const auto [section, param] = findParam(s, field);
    return section->qualified(param->key);
}

int keyLine(const Scenario& s, const void* field) {
    const std::optional<ParamLocation> at = locateParam(s, field);
    if (!at) return 0;
    const auto it = s.keyLines.find(lineKey(*at->section, at->param->key, at->record));
    return it == s.keyLines.end() ? 0 : it->second;
}

Scenario defaultScenario() {
    return parseScenarioString(kDefaultScenarioToml, "<built-in fig10>");
}

namespace {

/// The table at dotted `path` below `root`, made when missing.
toml::table& tableAt(toml::table& root, const std::string& path) {
    toml::table* t = &root;
    std::size_t from = 0;
    while (from < path.size()) {
        const std::size_t dot = std::min(path.find('.', from), path.size());
        const std::string part = path.substr(from, dot - from);
        if (!t->contains(part)) t->insert(part, toml::table{});
        t = t->get(part)->as_table();
        from = dot + 1;
    }
    return *t;
}

toml::array intArray(const std::vector<std::int64_t>& v, std::size_t from, std::size_t count) {
    toml::array a;
    for (std::size_t i = from; i < from + count; ++i) a.push_back(v[i]);
    return a;
}

/// Inserts entry `p` with value `v` into `t` (nothing for an absent `at` or `box`).
void insertValue(toml::table& t, const Param& p, const ParamValue& v) {
    switch (p.type) {
        case ParamType::kBool:
            t.insert(p.key, std::get<bool>(v));
            break;
        case ParamType::kInt:
            t.insert(p.key, std::get<std::int64_t>(v));
            break;
        case ParamType::kReal:
            t.insert(p.key, std::get<double>(v));
            break;
        case ParamType::kString:
        case ParamType::kChoice:
        case ParamType::kPath:
            t.insert(p.key, std::get<std::string>(v));
            break;
        case ParamType::kInt3:
        case ParamType::kIntList: {
            const auto& a = std::get<std::vector<std::int64_t>>(v);
            t.insert(p.key, intArray(a, 0, a.size()));
            break;
        }
        case ParamType::kReal3: {
            toml::array a;
            for (double x : std::get<std::vector<double>>(v)) a.push_back(x);
            t.insert(p.key, a);
            break;
        }
        case ParamType::kReal3List: {
            toml::array a;
            for (const Vec3d& x : std::get<std::vector<Vec3d>>(v)) a.push_back(toml::array{x[0], x[1], x[2]});
            t.insert(p.key, a);
            break;
        }
        case ParamType::kChoiceList: {
            toml::array a;
            for (const std::string& x : std::get<std::vector<std::string>>(v)) a.push_back(x);
            t.insert(p.key, a);
            break;
        }
        case ParamType::kVoxel: {
            const auto& a = std::get<std::vector<std::int64_t>>(v);
            if (!a.empty()) t.insert(p.key, intArray(a, 0, 3));
            break;
        }
        case ParamType::kVoxelBox: {
            const auto& a = std::get<std::vector<std::int64_t>>(v);
            if (!a.empty()) t.insert(p.key, toml::array{intArray(a, 0, 3), intArray(a, 3, 3)});
            break;
        }
    }
}

}  // namespace

toml::table scenarioTable(const Scenario& s, bool everyTable) {
    toml::table root;
    for (const ParamSection& section : scenarioParameters()) {
        if (section.isArray) {
            const std::size_t n = section.count(s);
            if (n == 0) continue;
            const std::size_t dot = section.path.rfind('.');
            toml::table& parent = tableAt(root, dot == std::string::npos ? "" : section.path.substr(0, dot));
            toml::array entries;
            for (std::size_t i = 0; i < n; ++i) {
                toml::table t;
                for (const Param& p : section.params)
                    if (!p.applies || p.applies(section.record(s, i))) insertValue(t, p, p.get(section.record(s, i)));
                entries.push_back(std::move(t));
            }
            parent.insert(section.path.substr(dot == std::string::npos ? 0 : dot + 1), std::move(entries));
        } else {
            if (section.omitAtDefaults && !everyTable &&
                std::all_of(section.params.begin(), section.params.end(),
                            [&](const Param& p) { return p.get(section.record(s, 0)) == p.get(section.defaults()); }))
                continue;
            toml::table& t = tableAt(root, section.path);
            for (const Param& p : section.params) insertValue(t, p, p.get(section.record(s, 0)));
        }
    }
    return root;
}

namespace {

std::string tomlText(const Scenario& s) {
    std::ostringstream os;
    os << "# Effective scenario: every key with its value, defaults filled in.\n" << scenarioTable(s) << "\n";
    return os.str();
}

}  // namespace

std::string scenarioToToml(const Scenario& s) {
    // toml++'s writer is checked, not trusted (3.3 mishandles some small negative floats): the text
    // must read back to a scenario that writes the very same text.
    const std::string text = tomlText(s);
    std::string again;
    try {
        again = tomlText(parseScenarioString(text, "<effective scenario>"));
    } catch (const InputError& e) {
        CAVESIM_CHECK(false, std::string("the effective scenario does not read back: ") + e.what());
    }
    CAVESIM_CHECK(again == text, "the effective scenario does not read back to the same values");
    return text;
}

}  // namespace cavesim
