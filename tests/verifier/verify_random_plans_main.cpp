// verify_random_plans: the random-graph plan check in bulk, for tools/verify-random-plans.sh.
//   verify_random_plans --seeds FIRST COUNT [--quiet]
// Each seed's graphs are compiled as verifyRandomGraph does (three or four plans) and verified.
// Prints each plan with unexpected findings (seed, variant, findings, and the graph unless
// --quiet), progress every 1000 seeds on stderr, and ends with
// "N verified, N findings (N plans alias)". Exit status 0 when
// there are no findings.
#include "verifier_test_util.hpp"

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
    uint32_t first = 1, count = 0;
    bool quiet = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--seeds" && i + 2 < argc) {
            first = static_cast<uint32_t>(std::strtoul(argv[i + 1], nullptr, 10));
            count = static_cast<uint32_t>(std::strtoul(argv[i + 2], nullptr, 10));
            i += 2;
        } else if (a == "--quiet") {
            quiet = true;
        } else {
            std::fprintf(stderr, "usage: %s --seeds FIRST COUNT [--quiet]\n", argv[0]);
            return 2;
        }
    }
    if (count == 0) {
        std::fprintf(stderr, "usage: %s --seeds FIRST COUNT [--quiet]\n", argv[0]);
        return 2;
    }
    skygraph::test::RandomResult result;
    size_t printed = 0;
    for (uint32_t seed = first; seed < first + count; ++seed) {
        skygraph::test::verifyRandomGraph(seed, result);
        for (; printed < result.failures.size(); ++printed) {
            const auto& f = result.failures[printed];
            std::printf("FINDINGS seed %u (%s):\n%s", f.seed, f.variant.c_str(), f.detail.c_str());
            if (!quiet) std::printf("%s\n", f.json.c_str());
        }
        if ((seed - first + 1) % 1000 == 0)
            std::fprintf(stderr, "%u seeds, %u plans, %u findings\n", seed - first + 1, result.plans, result.findings);
    }
    std::printf("%u verified, %u findings (%u plans alias)", result.plans, result.findings, result.aliasingPlans);
    if (result.compileErrors) std::printf(", %u did not compile", result.compileErrors);
    std::printf("\n");
    return result.failures.empty() ? 0 : 1;
}
