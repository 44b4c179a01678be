// drape's class templates for double (drape/instances.hpp).
#include "drape/instances.hpp"

namespace drape {
DRAPE_INSTANCES(template, double)
}  // namespace drape
