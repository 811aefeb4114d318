#include "sim/simulate.h"

#include "sim/stage1.h"
#include "sim/stage2.h"

namespace cavesim {

Domain simulate(const Scenario& s, const ProgressFn& progress) {
    Rng rng(s.seed);
    Domain d = buildDomain(s, rng);
    if (s.stage1.enabled) runStage1(d, s.stage1, rng, progress);
    if (s.stage2.enabled) {
        prepareStage2(d, s.stage2);
        runStage2(d, s.stage2, progress);
    }
    return d;
}

}  // namespace cavesim
