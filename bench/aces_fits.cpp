// aces_fits: the ACES fits' errors against the reference RRT + ODT (bench/aces_reference.hpp)
// alone, without study's renders. study prints the same table.
//
//   aces_fits [steps-per-stop, default 32]
#include "aces_reference.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

int main(int argc, char** argv) {
    CLI::App app{"aces_fits: the ACES fits' errors against the reference RRT + ODT"};
    int perStop = 32;
    app.add_option("steps-per-stop", perStop, "Grey-ramp steps per stop")->check(CLI::Range(1, 4096))->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        skygraph::aces::printFitTable(skygraph::aces::Reference(), perStop);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "aces_fits: %s\n", e.what());
        return 1;
    }
}
