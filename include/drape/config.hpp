#pragma once
/// \file config.hpp
/// The library version (the one place it is written: CMakeLists.txt reads it from here) and the
/// hot-loop assertion macro.
///
/// `DRAPE_ASSERT(cond, msg)` guards preconditions inside loops that run every step. It compiles to
/// `assert` by default; define it before including drape to route it to your own handler.
/// Constructors validate their arguments with exceptions instead (see core/validation.hpp).

#include <cassert>

#ifndef DRAPE_ASSERT
#define DRAPE_ASSERT(cond, msg) assert((cond) && (msg))
#endif

#define DRAPE_VERSION_MAJOR 0
#define DRAPE_VERSION_MINOR 2
#define DRAPE_VERSION_PATCH 0
