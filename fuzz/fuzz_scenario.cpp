// libFuzzer target: any bytes as a scenario file. Bad input must end in InputError; anything else
// escaping (another exception, a crash, a sanitizer report) is a finding. A scenario that parses
// is also validated and written back out (the effective scenario.toml), and that text must parse.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.h"
#include "sim/scenario_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > (1u << 16)) return 0;  // the parser's cost grows with size, not its coverage
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    cavesim::Scenario s;
    try {
        s = cavesim::parseScenarioString(text, "fuzz.toml");
        cavesim::validateScenario(s);
    } catch (const cavesim::InputError&) {
        return 0;
    }
    (void)cavesim::parseScenarioString(cavesim::scenarioToToml(s), "effective.toml");
    return 0;
}
