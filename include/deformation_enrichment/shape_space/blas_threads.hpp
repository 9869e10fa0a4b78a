#pragma once
// The BLAS threads of the shape-space solvers. CHOLMOD's supernodal factorisations call the process's BLAS;
// Debian's OpenBLAS (libopenblas0-pthread, installed for the 50k-tet Newton solves) then starts its own
// threads beside the solvers' OpenMP team, and on 2 cores the two pools spin and yield against each other
// (measured on the finger geodesic: 0.71-1.1 s with both pools, 0.55 s with a single-threaded BLAS; the
// shape-space factorisations, 6k unknowns, gain nothing from BLAS threads even alone: docs/design.md §10).
// The shape-space tools call this once at start-up; a library user decides for their own process.

namespace deformation_enrichment::shape_space {

/// Makes OpenBLAS, if it is the process's BLAS, run single-threaded, unless the user chose its thread count
/// (OPENBLAS_NUM_THREADS or GOTO_NUM_THREADS set). Returns true if it changed the setting; false with
/// another BLAS (it has no such setting) or when the user's choice stands.
bool preferSingleThreadedBlas();

/// OpenBLAS's current thread count, or 0 if the process's BLAS is not OpenBLAS.
int openBlasThreads();

/// Sets OpenBLAS's thread count (n >= 1); false if the process's BLAS is not OpenBLAS.
bool setOpenBlasThreads(int n);

}  // namespace deformation_enrichment::shape_space
