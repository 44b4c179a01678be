// drape's linear algebra and solvers for double (drape/instances.hpp). A source of its own, beside
// double_model.cpp: the two compile in parallel.
#include "drape/instances.hpp"

namespace drape {
DRAPE_SOLVER_INSTANCES(template, double)
}  // namespace drape
