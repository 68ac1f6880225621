// Discrete mean and Gaussian curvature and shape index per vertex: Meyer, Desbrun, Schröder &
// Barr, "Discrete differential-geometry operators for triangulated 2-manifolds" (2003).
#include "properties/curvature.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "base/vec3.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf::detail {
namespace {

Vec3 position(const Mesh& mesh, std::uint32_t v) {
    const float* p = &mesh.positions[3 * std::size_t{v}];
    return {p[0], p[1], p[2]};
}

// What one pass over the triangles gathers per vertex.
struct Accumulated {
    std::vector<double> area;   // mixed Voronoi area
    std::vector<double> angle;  // sum of the triangles' angles at the vertex
    std::vector<Vec3> laplace;  // Σ_j (cot α_ij + cot β_ij)(x_i - x_j)
    std::vector<Vec3> normal;   // Σ of the triangles' cross products (twice their area normal)
};

Accumulated accumulate(const Mesh& mesh, bool with_curvature) {
    const std::size_t nv = mesh.vertex_count();
    Accumulated acc;
    acc.area.assign(nv, 0.0);
    if (with_curvature) {
        acc.angle.assign(nv, 0.0);
        acc.laplace.assign(nv, Vec3{});
        acc.normal.assign(nv, Vec3{});
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* tri = &mesh.indices[3 * t];
        const Vec3 x[3] = {position(mesh, tri[0]), position(mesh, tri[1]), position(mesh, tri[2])};
        const Vec3 n = cross(sub(x[1], x[0]), sub(x[2], x[0]));
        const double twice_area = norm(n);
        // Corner k: its angle's cosine numerator (dot of the two edges leaving it) and cotangent.
        double dots[3], cots[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3 e1 = sub(x[(k + 1) % 3], x[k]), e2 = sub(x[(k + 2) % 3], x[k]);
            dots[k] = dot(e1, e2);
            if (with_curvature) acc.angle[tri[k]] += std::atan2(norm(cross(e1, e2)), dots[k]);
        }
        if (!(twice_area > 0.0) || !std::isfinite(twice_area)) continue;  // angles only
        for (int k = 0; k < 3; ++k) cots[k] = dots[k] / twice_area;
        if (with_curvature) {
            for (int k = 0; k < 3; ++k) {
                for (int a = 0; a < 3; ++a) acc.normal[tri[k]][a] += n[a];
                // The edge opposite corner k joins i = k + 1 and j = k + 2, weighted cot k.
                const int i = (k + 1) % 3, j = (k + 2) % 3;
                const Vec3 d = sub(x[i], x[j]);
                for (int a = 0; a < 3; ++a) {
                    acc.laplace[tri[i]][a] += cots[k] * d[a];
                    acc.laplace[tri[j]][a] -= cots[k] * d[a];
                }
            }
        }
        const double area = 0.5 * twice_area;
        const int obtuse = dots[0] < 0.0 ? 0 : dots[1] < 0.0 ? 1 : dots[2] < 0.0 ? 2 : -1;
        for (int k = 0; k < 3; ++k) {
            double a = 0.0;
            if (obtuse < 0) {
                // Voronoi region of P = k: 1/8 (|PR|² cot Q + |PQ|² cot R), Q = k + 1, R = k + 2.
                const int q = (k + 1) % 3, r = (k + 2) % 3;
                const Vec3 pq = sub(x[q], x[k]), pr = sub(x[r], x[k]);
                a = (dot(pr, pr) * cots[q] + dot(pq, pq) * cots[r]) / 8.0;
            } else {
                a = obtuse == k ? 0.5 * area : 0.25 * area;
            }
            acc.area[tri[k]] += a;
        }
    }
    return acc;
}

// Vertices on an edge used by exactly one triangle.
std::vector<char> boundary_vertices(const Mesh& mesh) {
    std::vector<std::uint64_t> edges;
    edges.reserve(mesh.indices.size());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.indices[3 * t + k], b = mesh.indices[3 * t + (k + 1) % 3];
            if (a != b) edges.push_back(std::uint64_t{std::min(a, b)} << 32 | std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    std::vector<char> boundary(mesh.vertex_count(), 0);
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) {
            boundary[edges[i] >> 32] = 1;
            boundary[edges[i] & 0xffffffffu] = 1;
        }
        i = j;
    }
    return boundary;
}

// Passes of x_i <- Σ A_j x_j / Σ A_j over the corners j of vertex i's triangles (i included; a
// vertex counted once per triangle it shares with i). A vertex without area keeps its values.
void smooth(const Mesh& mesh, const std::vector<double>& area, int passes, std::vector<double>& h,
            std::vector<double>& k) {
    const std::size_t nv = mesh.vertex_count();
    std::vector<double> h_sum(nv), k_sum(nv), weight(nv);
    for (int pass = 0; pass < passes; ++pass) {
        std::fill(h_sum.begin(), h_sum.end(), 0.0);
        std::fill(k_sum.begin(), k_sum.end(), 0.0);
        std::fill(weight.begin(), weight.end(), 0.0);
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const std::uint32_t* tri = &mesh.indices[3 * t];
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) {
                    const std::uint32_t i = tri[a], j = tri[b];
                    h_sum[i] += area[j] * h[j];
                    k_sum[i] += area[j] * k[j];
                    weight[i] += area[j];
                }
            }
        }
        for (std::size_t v = 0; v < nv; ++v) {
            if (!(weight[v] > 0.0)) continue;
            h[v] = h_sum[v] / weight[v];
            k[v] = k_sum[v] / weight[v];
        }
    }
}

}  // namespace

std::vector<double> vertex_mixed_area(const Mesh& mesh) {
    validate_mesh(mesh, "vertex_mixed_area", true);
    return accumulate(mesh, false).area;
}

VertexCurvature vertex_curvature(const Mesh& mesh, int smoothing_passes) {
    validate_mesh(mesh, "vertex_curvature", true);
    if (smoothing_passes < 0) {
        throw Error(ErrorCode::InvalidArgument, "vertex_curvature: negative smoothing passes");
    }
    const std::size_t nv = mesh.vertex_count();
    const Accumulated acc = accumulate(mesh, true);
    const std::vector<char> boundary = boundary_vertices(mesh);
    const bool own_normals = mesh.normals.size() == mesh.positions.size();
    std::vector<double> h(nv, 0.0), k(nv, 0.0);
    std::vector<char> known(nv, 0);  // interior vertices with an area
    for (std::size_t v = 0; v < nv; ++v) {
        const double area = acc.area[v];
        if (!(area > 0.0)) continue;
        const Vec3 normal = own_normals ? Vec3{mesh.normals[3 * v], mesh.normals[3 * v + 1],
                                               mesh.normals[3 * v + 2]}
                                        : acc.normal[v];
        const double normal_length = norm(normal);
        Vec3 kn;  // the mean-curvature normal 2 H n
        for (int a = 0; a < 3; ++a) kn[a] = acc.laplace[v][a] / (2.0 * area);
        const double along = normal_length > 0.0 ? dot(kn, normal) / normal_length : 0.0;
        if (boundary[v]) {
            // The half ring's own estimate, used when no interior neighbour does better below.
            h[v] = 0.5 * along;
            k[v] = (std::numbers::pi - acc.angle[v]) / area;
        } else {
            h[v] = along < 0.0 ? -0.5 * norm(kn) : 0.5 * norm(kn);
            k[v] = (2.0 * std::numbers::pi - acc.angle[v]) / area;
            known[v] = 1;
        }
    }
    // Border vertices take the mean of their interior neighbours' values (one count per
    // triangle they share).
    std::vector<double> h_sum(nv, 0.0), k_sum(nv, 0.0);
    std::vector<std::uint32_t> count(nv, 0);
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* tri = &mesh.indices[3 * t];
        for (int a = 0; a < 3; ++a) {
            if (!boundary[tri[a]]) continue;
            for (int b = 0; b < 3; ++b) {
                if (!known[tri[b]]) continue;
                h_sum[tri[a]] += h[tri[b]];
                k_sum[tri[a]] += k[tri[b]];
                ++count[tri[a]];
            }
        }
    }
    for (std::size_t v = 0; v < nv; ++v) {
        if (count[v] > 0) {
            h[v] = h_sum[v] / double(count[v]);
            k[v] = k_sum[v] / double(count[v]);
        }
    }
    if (smoothing_passes > 0) smooth(mesh, acc.area, smoothing_passes, h, k);
    VertexCurvature out;
    out.mean.resize(nv);
    out.gaussian.resize(nv);
    out.shape_index.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        // k1 + k2 = 2H, k1 - k2 = 2 sqrt(max(H² - K, 0)) >= 0: atan2 gives ±π/2 at umbilics
        // and 0 where both vanish.
        const double s =
            2.0 / std::numbers::pi * std::atan2(h[v], std::sqrt(std::max(h[v] * h[v] - k[v], 0.0)));
        out.mean[v] = float(h[v]);
        out.gaussian[v] = float(k[v]);
        out.shape_index[v] = float(s);
    }
    return out;
}

}  // namespace fdmsurf::detail
