// aces_fits: the ACES fits' errors against the reference RRT + ODT (bench/aces_reference.hpp)
// alone, without study's renders. study prints the same table.
//
//   aces_fits [steps-per-stop, default 32]
#include "aces_reference.hpp"

#include <cstdio>
#include <exception>
#include <string>

int main(int argc, char** argv) {
    try {
        const int perStop = argc > 1 ? std::stoi(argv[1]) : 32;
        if (perStop < 1) throw std::invalid_argument("steps per stop must be >= 1");
        skygraph::aces::printFitTable(skygraph::aces::Reference(), perStop);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "aces_fits: %s\n", e.what());
        return 1;
    }
}
