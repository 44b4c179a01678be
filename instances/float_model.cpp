// drape's cloth model, forces, collisions, integrators and scene for float (drape/instances.hpp).
#include "drape/instances.hpp"

namespace drape {
DRAPE_MODEL_INSTANCES(template, float)
}  // namespace drape
