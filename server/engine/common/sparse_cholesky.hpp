// A sparse symmetric positive definite factorisation, factored once and
// solved many times (the mesh flattening's Laplacian and its conformal
// start). CHOLMOD's supernodal Cholesky (SuiteSparse, Debian's
// libsuitesparse-dev) where the build found it: on a 50k-vertex mesh's
// ring-3 Laplacian it factors 2.3x and solves 3.8x faster than Eigen's
// SimplicialLDLT, on Debian's serial OpenBLAS (BENCHMARKS.md; the serial
// build starts no threads of its own, which would take the server's
// SIGTERM before it blocks signals). Eigen's SimplicialLDLT otherwise.
// Same answers to rounding.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

namespace surfdeform {

class SparseCholesky {
 public:
  // Factors `a`, of which only the lower triangle is read.
  explicit SparseCholesky(const Eigen::SparseMatrix<double>& a);
  ~SparseCholesky();
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  bool ok() const;  // the factorisation succeeded (the matrix is positive definite)
  // A^-1 b. Not for concurrent calls on one factor.
  Eigen::MatrixXd Solve(const Eigen::MatrixXd& b) const;
  // Which factorisation this build uses: "cholmod" or "eigen".
  static const char* Backend();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace surfdeform
