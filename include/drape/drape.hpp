#pragma once
/// \file drape.hpp
/// Umbrella header: everything in the header-only core. Include single headers to compile faster.

#include "drape/config.hpp"
#include "drape/fwd.hpp"
#include "drape/core/cloth.hpp"
#include "drape/core/grid.hpp"
#include "drape/core/parallel.hpp"
#include "drape/core/pins.hpp"
#include "drape/core/spring_set.hpp"
#include "drape/core/state.hpp"
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/physics/spring_kernel.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/integrators/step_status.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/io/atomic_file.hpp"
#include "drape/io/obj.hpp"
#include "drape/io/state_io.hpp"
#include "drape/realtime/realtime_driver.hpp"
