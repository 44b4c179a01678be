#pragma once
// The precompiled header of every test program but the STANDALONE ones (tests/CMakeLists.txt):
// Catch2, Eigen, every drape header and the declarations of the compiled instances
// (drape/instances.hpp), parsed once for all of them. Each test source still includes what it
// uses, so it also builds without precompiled headers.
#include <catch2/catch.hpp>

#include <Eigen/Dense>

#include "drape/instances.hpp"
#include "support/dense.hpp"
