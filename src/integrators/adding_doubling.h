// A deterministic solver for a plane-parallel, homogeneous, index-matched slab with isotropic
// scattering under normal collimated illumination: total diffuse reflectance and transmittance
// by adding-doubling [vandeHulst80 ch. 5; Prahl95]. It shares no code with the Monte Carlo path
// tracer (path_tracer.h) and serves as its reference where a published table value is not at
// hand. Also Chandrasekhar's H-function of isotropic scattering [Chandrasekhar60 ch. V], whose
// plane albedo 1 - H(1) sqrt(1 - a) checks the solver in the semi-infinite limit.
#pragma once

namespace veil::volume {

struct SlabReflectance {
    double reflectance = 0.0;          // diffuse, back into the upper hemisphere
    double diffuseTransmittance = 0.0; // scattered at least once, out through the bottom
    double directTransmittance = 0.0;  // exp(-tau)
};

// `tau` optical thickness, `albedo` single-scattering albedo in [0, 1]; `nodes` Gauss-Legendre
// directions per hemisphere. The starting layer is thin enough (tau / 2^n <= 2^-30) that its
// first-order (single-scattering) operators make an error far below 1e-6.
SlabReflectance addingDoublingSlab(double tau, double albedo, int nodes = 24);

// H(mu) of isotropic scattering with albedo a in (0, 1) (a = 1 converges too slowly), by the
// fixed-point iteration of its integral equation on a Gauss-Legendre grid.
double chandrasekharH(double mu, double albedo);

} // namespace veil::volume
