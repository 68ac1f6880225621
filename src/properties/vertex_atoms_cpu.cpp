// Brute-force references of shaders/vertex_atoms.comp and shaders/coulombic.comp.
#include "properties/vertex_atoms_cpu.hpp"

#include <algorithm>
#include <limits>

#include "properties/vertex_properties_gpu.hpp"

namespace fdmsurf::detail {

double power_distance(const Mesh& mesh, std::size_t v, const Atoms& atoms, std::size_t i,
                      float radius_add) {
    double d2 = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double d = double(mesh.positions[3 * v + k]) - double(atoms.xyz[3 * i + k]);
        d2 += d * d;
    }
    const double r = double(atoms.radius[i]) + double(radius_add);
    return d2 - r * r;
}

std::vector<std::uint32_t> vertex_atoms_cpu(const Mesh& mesh, const Atoms& atoms,
                                            float radius_add) {
    std::vector<std::uint32_t> out(mesh.vertex_count());
    for (std::size_t v = 0; v < out.size(); ++v) {
        double best = std::numeric_limits<double>::infinity();
        std::uint32_t best_atom = 0;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const double pw = power_distance(mesh, v, atoms, i, radius_add);
            if (pw < best) {  // strict: ties keep the lower index
                best = pw;
                best_atom = static_cast<std::uint32_t>(i);
            }
        }
        out[v] = best_atom;
    }
    return out;
}

std::vector<std::uint32_t> vertex_atoms_float_cpu(const float* positions, std::size_t n,
                                                  const Atoms& atoms, float radius_add) {
    std::vector<float> r2(atoms.size());
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const float r = atoms.radius[i] + radius_add;
        r2[i] = r * r;
    }
    std::vector<std::uint32_t> out(n);
    for (std::size_t v = 0; v < n; ++v) {
        const float* p = positions + 3 * v;
        float best = 3.0e38f;
        std::uint32_t best_atom = 0xffffffffu;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            const float d0 = p[0] - atoms.xyz[3 * i], d1 = p[1] - atoms.xyz[3 * i + 1],
                        d2 = p[2] - atoms.xyz[3 * i + 2];
            const float pw = (d0 * d0 + d1 * d1 + d2 * d2) - r2[i];
            if (pw < best) {  // strict: ties keep the lower index
                best = pw;
                best_atom = static_cast<std::uint32_t>(i);
            }
        }
        out[v] = best_atom;
    }
    return out;
}

std::vector<double> coulombic_cpu(const Mesh& mesh, const Atoms& atoms,
                                  const std::vector<float>& charges, float offset) {
    std::vector<double> out(mesh.vertex_count());
    for (std::size_t v = 0; v < out.size(); ++v) {
        double x[3];
        for (int k = 0; k < 3; ++k)
            x[k] = double(mesh.positions[3 * v + k]) + double(offset) * mesh.normals[3 * v + k];
        double phi = 0.0;
        for (std::size_t i = 0; i < atoms.size(); ++i) {
            if (charges[i] == 0.0f) continue;
            double d2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                const double d = x[k] - double(atoms.xyz[3 * i + k]);
                d2 += d * d;
            }
            phi += double(charges[i]) / std::max(d2, 1e-2);
        }
        out[v] = kCoulombScale * phi;
    }
    return out;
}

}  // namespace fdmsurf::detail
