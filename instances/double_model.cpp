// drape's cloth model, physics, integrators and scene for double (drape/instances.hpp).
#include "drape/instances.hpp"

namespace drape {
DRAPE_MODEL_INSTANCES(template, double)
}  // namespace drape
