// drape's linear algebra and solvers for float, which the double programs' single-precision
// multigrid preconditioner uses too (drape/instances.hpp).
#include "drape/instances.hpp"

namespace drape {
DRAPE_SOLVER_INSTANCES(template, float)
}  // namespace drape
