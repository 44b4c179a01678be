#pragma once
// Dense linear algebra the tests check against, compiled once (dense.cpp): Eigen's dense
// decompositions take seconds to compile in every test source that uses them.
#include <Eigen/Core>

namespace drape::test {

/// The eigenvalues of the symmetric matrix `a` (its lower triangle is read), ascending.
Eigen::VectorXd symmetric_eigenvalues(const Eigen::MatrixXd& a);

/// Does the Cholesky factorisation of the symmetric matrix `a` succeed (is it positive definite)?
bool cholesky_succeeds(const Eigen::MatrixXd& a);

/// x with a x = b for a symmetric positive definite `a` (Cholesky).
Eigen::VectorXd solve_spd(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

/// x with a x = b for any invertible `a` (LU with partial pivoting).
Eigen::VectorXd solve_general(const Eigen::MatrixXd& a, const Eigen::VectorXd& b);

}  // namespace drape::test
