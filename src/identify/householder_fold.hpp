// Private: the kernel of streaming identification (streaming.hpp), folding a
// block of rows into an upper-triangular factor by Householder reflections.
#pragma once

namespace massid::detail {

// R <- the triangular factor of the QR of [R; B]: R n x n upper triangular,
// column-major; B m x n column-major with leading dimension ldb (destroyed).
// Householder reflections as LAPACK's dlarfg; the reflector of column k is
// [e_k; v], so it touches row k of R and the m rows of B only: 2 m n^2 flops.
// The result is bit-identical on every x86-64 (the AVX2 clone does the same
// operations in the same order as the SSE2 one, and never contracts to FMA).
void fold_rows(double* R, int n, double* B, int m, int ldb);

}  // namespace massid::detail
