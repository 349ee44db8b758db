// Private: the kernel of streaming identification (streaming.hpp), folding a
// block of rows into an upper-triangular factor by Householder reflections.
#pragma once

#include <Eigen/Core>

namespace massid::detail {

// R <- the triangular factor of the QR of [R; B]: R n x n upper triangular,
// column-major; B m x n column-major with leading dimension ldb (destroyed).
// Householder reflections as LAPACK's dlarfg; the reflector of column k is
// [e_k; v], so it touches row k of R and the m rows of B only: 2 m n^2 flops.
// The result is bit-identical on every x86-64 (the AVX2 clone does the same
// operations in the same order as the SSE2 one, and never contracts to FMA).
void fold_rows(double* R, int n, double* B, int m, int ldb);

// Rows per chunk folded at once. 128 rows x 16 columns of doubles is 16 KB
// per moment axis: the chunk stays in L1/L2 while it is reduced, and the
// per-chunk overhead (the n x n triangle's rows) is small against 2 m n^2.
constexpr int kChunk = 128;

// The triangular factor of rows folded a chunk at a time: rows are written
// to B, by add() or straight into its columns, then folded.
struct FoldedRows {
  Eigen::MatrixXd R, B;  // [n x n] upper triangular; [chunk x n] rows not yet folded
  int pending = 0;       // rows written by add()
  FoldedRows(int n = 0, int chunk = 0) : R(Eigen::MatrixXd::Zero(n, n)), B(chunk, n) {}
  int n() const { return static_cast<int>(R.rows()); }  // columns
  void add(const Eigen::RowVectorXd& z);                // (folded once B is full)
  void fold(int m);                                     // the first m rows of B
  void flush();                                         // the rows written by add()
  void merge(FoldedRows& later);                        // later's rows after these (both flushed)
};

}  // namespace massid::detail
