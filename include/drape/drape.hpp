#pragma once
/// \file drape.hpp
/// Umbrella header: everything in the header-only core except the opt-in and optional solvers
/// (solvers/enable_ldlt.hpp, enable_lu.hpp; cholmod.hpp and umfpack.hpp with SuiteSparse).
/// Include single headers to compile faster. The groups below are the layers, each using only
/// the ones above it (drape's architecture.md). The pages the headers cite as "drape's X.md" are
/// in docs/ of the source and in share/doc/drape of an installation.

#include "drape/config.hpp"
#include "drape/fwd.hpp"

// platform: threads, the run-time instruction set, exact vector square roots, a portable sine
#include "drape/platform/team.hpp"
#include "drape/platform/sine.hpp"
#include "drape/platform/instruction_set.hpp"
#include "drape/platform/vector_sqrt.hpp"

// core: types, checks, option names, the parts of the cloth model, meshes and their generators
#include "drape/core/types.hpp"
#include "drape/core/validation.hpp"
#include "drape/core/enum_names.hpp"
#include "drape/core/instruction_set_choice.hpp"
#include "drape/core/grid.hpp"
#include "drape/core/cloth_mesh.hpp"
#include "drape/core/mesh_generators.hpp"
#include "drape/core/spring_set.hpp"
#include "drape/core/pins.hpp"
#include "drape/core/pin_path.hpp"
#include "drape/core/pin_set.hpp"
#include "drape/core/state.hpp"
#include "drape/core/force_term.hpp"
#include "drape/core/placement.hpp"
#include "drape/core/solid_generators.hpp"

// linalg: 3x3 block storage and the linear system solvers are handed
#include "drape/linalg/block3.hpp"
#include "drape/linalg/block_sparse_matrix.hpp"
#include "drape/linalg/edge_operator.hpp"
#include "drape/linalg/grid_layout.hpp"
#include "drape/linalg/constraint_filter.hpp"
#include "drape/linalg/linear_system.hpp"
#include "drape/linalg/filtered_system.hpp"

// collision: cloth-cloth and cloth-mesh geometry (closest points, continuous tests, the tree, a
// mesh's signed distance, still and deforming)
#include "drape/collision/primitive_distance.hpp"
#include "drape/collision/continuous_collision.hpp"
#include "drape/collision/mesh_topology.hpp"
#include "drape/collision/bounding_volume_hierarchy.hpp"
#include "drape/collision/mesh_distance.hpp"
#include "drape/collision/mesh_sweep.hpp"

// contact: colliders and self-collision, their settings and the handlers that resolve them
#include "drape/contact/collider.hpp"
#include "drape/contact/self_collision_settings.hpp"
#include "drape/contact/contact_handler.hpp"
#include "drape/contact/self_collision.hpp"

// model: the cloth composed of core's parts and contact's settings
#include "drape/model/cloth.hpp"

// physics: forces, their derivatives, the system assembly, diagnostics, drape measures
#include "drape/physics/spring_kernel.hpp"
#include "drape/physics/spring_jacobian.hpp"
#include "drape/physics/spring_families.hpp"
#include "drape/physics/force_assembler.hpp"
#include "drape/physics/jacobian_assembler.hpp"
#include "drape/physics/wind_field.hpp"
#include "drape/physics/air_drag.hpp"
#include "drape/physics/aerodynamic_force.hpp"
#include "drape/physics/air.hpp"
#include "drape/physics/dihedral_bending.hpp"
#include "drape/physics/ramped_gravity.hpp"
#include "drape/physics/seam_springs.hpp"
#include "drape/physics/diagnostics.hpp"
#include "drape/physics/drape_measures.hpp"

// solvers: linear solvers and preconditioners (know nothing of cloth)
#include "drape/solvers/solve_status.hpp"
#include "drape/solvers/preconditioner.hpp"
#include "drape/solvers/linear_solver.hpp"
#include "drape/solvers/solver_kind.hpp"
#include "drape/solvers/block_jacobi.hpp"
#include "drape/solvers/dense_cholesky.hpp"
#include "drape/solvers/multigrid_hierarchy.hpp"
#include "drape/solvers/multigrid.hpp"
#include "drape/solvers/single_precision_multigrid.hpp"
#include "drape/solvers/aggregation_hierarchy.hpp"
#include "drape/solvers/algebraic_multigrid.hpp"
#include "drape/solvers/single_precision_algebraic_multigrid.hpp"
#include "drape/solvers/make_preconditioner.hpp"
#include "drape/solvers/pcg.hpp"
#include "drape/solvers/bicgstab.hpp"
#include "drape/solvers/direct_solver.hpp"
#include "drape/solvers/solver_registry.hpp"

// integrators: time stepping
#include "drape/integrators/step_status.hpp"
#include "drape/integrators/integrator.hpp"
#include "drape/integrators/explicit_integrator.hpp"
#include "drape/integrators/rk2.hpp"
#include "drape/integrators/symplectic_euler.hpp"
#include "drape/integrators/implicit_euler.hpp"
#include "drape/integrators/make_integrator.hpp"

// scene: several cloths stepped together, colliding with each other
#include "drape/scene/cloth_scene.hpp"

// garment (sewing patterns, panels meshed, the garment as one cloth mesh): included on its own,
// drape/garment/garment_mesh.hpp and the headers below it, not by every user of the umbrella

// realtime and io: pacing against the wall clock, files
#include "drape/realtime/realtime_driver.hpp"
#include "drape/io/atomic_file.hpp"
#include "drape/io/obj.hpp"
#include "drape/io/state_io.hpp"
#include "drape/io/usd.hpp"
