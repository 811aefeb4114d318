/// @file parameters.h
/// @brief The parameter registry: every scenario key declared once (docs/scenario-format.md).
///
/// Each key is one `Param` entry in src/sim/parameters.cpp: its TOML key, type, unit, allowed
/// range, one-line description, for a choice its names mapped to the enum values, and accessors
/// that read and write the struct member it sets. Keys are grouped in `ParamSection`s, one per TOML
/// table; a table of arrays (`[[source]]`) is a section whose entries are records of a vector.
/// The parser and the effective-scenario writer (scenario_io.cpp), the report's parameter table,
/// `cavesim reference` and docs/scenario-format.md are all made from it. To add a key: add one
/// entry to its section in parameters.cpp, then use the member.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "sim/scenario.h"

namespace cavesim {

/// What a key holds in the file.
enum class ParamType : std::uint8_t {
    kBool,
    kInt,         ///< whole number (int, long or the 64-bit seed)
    kReal,        ///< number (integers accepted)
    kString,      ///< a name: 1-64 letters, digits, '-' or '_'
    kChoice,      ///< one name of `choices`
    kInt3,        ///< [int, int, int]
    kReal3,       ///< [x, y, z]
    kReal3List,   ///< [[x, y, z], …]
    kChoiceList,  ///< [name, …], each a name of `choices`, distinct
    kIntList,     ///< [int, …]
    kVoxel,       ///< `at = [x, y, z]`: a one-voxel box (the record's box)
    kVoxelBox,    ///< `box = [[x0, y0, z0], [x1, y1, z1]]` (the record's box)
    kPath,        ///< a file path (relative to the scenario file's folder), or "" for none
};

/// A key's value, independent of the struct it lives in: integers and choices as written in TOML.
using ParamValue = std::variant<bool, std::int64_t, double, std::string, std::vector<std::int64_t>, std::vector<double>,
                                std::vector<std::string>, std::vector<Vec3d>>;

/// Allowed numeric range; `domainScaled` multiplies both ends by 4 × the largest domain size.
struct ParamRange {
    double lo = 0, hi = 0;
    bool loOpen = false, hiOpen = false;
    bool domainScaled = false;
};

/// A choice's name and its enum value (as an int).
struct ParamChoice {
    const char* name;
    int value;
};

/// One scenario key.
struct Param {
    std::string key;  ///< key inside its section's table
    ParamType type = ParamType::kReal;
    std::string unit = "–";
    ParamRange range;         ///< numbers, and each element of a numeric array
    std::string rangeText;    ///< range as shown in the reference (made from `range` when empty)
    std::string defaultText;  ///< default as shown in the reference (the default value when empty)
    std::string description;  ///< one line
    std::vector<ParamChoice> choices;
    bool required = false;
    bool nonZero = false;                    ///< a vector: the zero vector is refused ("must not be zero")
    std::size_t minItems = 0, maxItems = 0;  ///< lists: bounds on the number of elements (0 = none)
    std::string shapeText;                   ///< lists and names: what the value must be, for messages ("must be …")
    std::string example;                     ///< TOML value used by the example scenario for a required key
    /// Reads the member of `record` (the section's struct).
    std::function<ParamValue(const void* record)> get;
    /// Writes the member of `record` from a value already checked against type and range.
    std::function<void(void* record, const ParamValue&)> set;
    /// The member's address inside `record` (for `scenarioKey`).
    std::function<const void*(const void* record)> address;
    /// Whether the key applies to `record` (empty: always). A key that does not apply is refused by
    /// the parser when the file gives it, with `notApplicable` as the reason, and left out of the
    /// effective scenario. Checked after every key of the record has been read.
    std::function<bool(const void* record)> applies;
    std::string notApplicable;  ///< why the key does not apply, for messages ("only sinkholes take …")
};

/// One TOML table (or table of arrays) of keys.
struct ParamSection {
    std::string path;            ///< dotted table path; "" for the top level
    bool isArray = false;        ///< a table of arrays ([[path]]): records of a vector
    std::size_t maxEntries = 0;  ///< table of arrays: at most this many entries
    /// A plain table left out of the effective scenario when every key holds its default (a table
    /// added later, so scenarios without it write the same text as before).
    bool omitAtDefaults = false;
    /// A table of arrays that, when written, must have at least one entry (`phase = []` is refused).
    bool nonEmpty = false;
    /// When set, the entry limit is checked entry by entry and the message gives this reason.
    std::string limitReason;
    std::string heading;  ///< reference heading after the table name
    std::string prose;    ///< reference text before the key table
    std::string notes;    ///< reference text after the key table
    /// The example scenario shows this section commented out (its entries name files that the
    /// example does not ship).
    bool exampleCommented = false;
    /// Why it is commented out (shown after the header); empty = it needs files the example lacks.
    std::string exampleNote;
    std::vector<Param> params;
    /// The records: one for a table, the vector's elements for a table of arrays.
    std::function<std::size_t(const Scenario&)> count;
    std::function<const void*(const Scenario&, std::size_t)> record;
    std::function<void*(Scenario&, std::size_t)> mutableRecord;
    /// A table of arrays: appends a default record and returns it.
    std::function<void*(Scenario&)> append;
    /// Records the line of the table (of an entry, for a table of arrays) in the file (for messages).
    std::function<void(void* record, int line)> setLine;
    /// A default record (for defaults of a table of arrays' keys).
    std::function<const void*()> defaults;

    /// The entry with key `key`; throws RuntimeError when there is none.
    const Param& param(const std::string& key) const;
    /// "[path]" or "[[path]]".
    std::string header() const;
    /// `path + "." + key`, or `key` at the top level.
    std::string qualified(const std::string& key) const;
};

/// Every section, in file order: top level, domain, rock, rock.noise, rock.sphere, rock.plane,
/// rock.channel, rock.inception_horizon, rock.fracture_family, source, sink, recharge, stage1, stage2,
/// hydrology, phase, output, site, site.horizon, speleothems.
const std::vector<ParamSection>& scenarioParameters();

/// The section at `path` ("stage2", "rock.sphere"); throws RuntimeError when there is none.
const ParamSection& paramSection(const std::string& path);

/// Where a field of a scenario is registered: its section, its entry, and which record of the
/// section holds it (0 for a plain table; the entry's index in a table of arrays).
struct ParamLocation {
    const ParamSection* section = nullptr;
    const Param* param = nullptr;
    std::size_t record = 0;
};

/// The location of the field at address `field` of `scenario`, or nothing when it is not a
/// registered field.
std::optional<ParamLocation> locateParam(const Scenario& scenario, const void* field);

/// The section and entry of the field at address `field` of `scenario` (a table's member only).
/// @throw RuntimeError if `field` is not a registered field
std::pair<const ParamSection*, const Param*> findParam(const Scenario& scenario, const void* field);

/// `value` as written in TOML (`0.5`, `"max"`, `[1, 2, 3]`).
std::string paramValueText(const ParamValue& value);

/// The allowed range of `p` as the reference shows it ("(0, 10⁶]", "1–64", the choice names).
std::string paramRangeText(const Param& p);

/// The scenario reference in Markdown (docs/scenario-format.md is exactly this text).
std::string scenarioReferenceMarkdown();

/// A complete scenario: every key with its default and a comment with unit, range and meaning.
std::string exampleScenarioToml();

/// The report's parameter table (Markdown): every key of the plain tables with its value; a value
/// that differs from the default is shown in bold with the default beside it.
std::string parameterTableMarkdown(const Scenario& scenario);

}  // namespace cavesim
