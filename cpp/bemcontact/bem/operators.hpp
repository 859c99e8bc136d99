// Collocation BEM influence matrices with the Kelvin fundamental solution:
// the dense H and G, and the mixed system assembled without storing them
// (element integrals from bem/integration.hpp).
#pragma once

#include <cstdint>

#include "bem/integration.hpp"

namespace bemcontact {

// Full H and G (3N x 3N, row-major), N = number of functional nodes; the
// diagonal blocks of H (free term + principal value) come from rigid-body
// translation.  Points: (N, 3) collocation points.
void assemble_influence(const MeshView& m, const double* points, int64_t n_points,
                        double shear_modulus, double nu, const QuadratureParams& q,
                        int threads, double* H, double* G);

// The mixed system A x = b in place, without H and G: A (column-major,
// leading dimension lda >= 3N, so a bordered matrix can hold it) has the
// columns of H where the traction is given and of -G where the displacement
// is given (known_u, 3N); B (G resp. -H) is applied to W (3N x s, row-major)
// into BW (3N x s) and its columns bcols (nb) are copied into BC (3N x nb,
// row-major).
void assemble_system(const MeshView& m, const double* points, int64_t n_points,
                     double shear_modulus, double nu, const QuadratureParams& q,
                     const uint8_t* known_u, const double* W, int64_t s, const int64_t* bcols,
                     int64_t nb, int threads, double* A, int64_t lda, double* BW, double* BC);

}  // namespace bemcontact
