// Compile-time probe (scripts/bench.sh): the umbrella header and nothing else.
#include <drape/drape.hpp>
int main() { return 0; }
