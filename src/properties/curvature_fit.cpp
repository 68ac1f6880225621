// Curvature by local quadric fitting (Goldfeather & Interrante 2004, "A novel cubic-order
// algorithm for approximating principal direction vectors", ACM TOG 23(1); the fit libigl's
// principal_curvature uses, Panozzo et al. 2010): robust to the slivers of marching cubes.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "base/parallel.hpp"
#include "base/vec3.hpp"
#include "fdmsurf/error.hpp"
#include "properties/curvature.hpp"

namespace fdmsurf::detail {

namespace {

// The neighbourhood of a vertex stops growing at this many vertices (a fine mesh with a large
// fit radius); at the default radius of two grid spacings there are some 30 to 60.
constexpr std::size_t kMaxNeighbours = 4096;

Vec3 vertex(const Mesh& m, std::size_t v) {
    return {m.positions[3 * v], m.positions[3 * v + 1], m.positions[3 * v + 2]};
}
Vec3 unit(Vec3 a) {
    const double n = std::sqrt(dot(a, a));
    if (n > 0) a = {a[0] / n, a[1] / n, a[2] / n};
    return a;
}

// Solves the 5x5 symmetric system a x = b by Gaussian elimination with partial pivoting;
// false when singular.
bool solve5(std::array<std::array<double, 6>, 5> a, std::array<double, 5>& x) {
    for (int c = 0; c < 5; ++c) {
        int p = c;
        for (int r = c + 1; r < 5; ++r)
            if (std::abs(a[r][c]) > std::abs(a[p][c])) p = r;
        if (std::abs(a[p][c]) < 1e-14) return false;
        std::swap(a[p], a[c]);
        for (int r = c + 1; r < 5; ++r) {
            const double f = a[r][c] / a[c][c];
            for (int k = c; k < 6; ++k) a[r][k] -= f * a[c][k];
        }
    }
    for (int r = 4; r >= 0; --r) {
        double s = a[r][5];
        for (int k = r + 1; k < 5; ++k) s -= a[r][k] * x[k];
        x[r] = s / a[r][r];
    }
    return true;
}

}  // namespace

VertexCurvature fitted_curvature(const Mesh& mesh, float radius) {
    const std::size_t nv = mesh.vertex_count();
    if (mesh.normals.size() != mesh.positions.size())
        throw Error(ErrorCode::InvalidArgument, "curvature: the mesh has no vertex normals");
    // Vertex neighbours (CSR) from the triangles.
    std::vector<std::uint32_t> count(nv + 1, 0);
    for (std::uint32_t i : mesh.indices) {
        if (i >= nv) throw Error(ErrorCode::InvalidArgument, "curvature: index out of range");
        count[i + 1] += 2;
    }
    for (std::size_t v = 0; v < nv; ++v) count[v + 1] += count[v];
    std::vector<std::uint32_t> adj(count[nv]), fill(count.begin(), count.end() - 1);
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = mesh.indices[t + k];
            adj[fill[a]++] = mesh.indices[t + (k + 1) % 3];
            adj[fill[a]++] = mesh.indices[t + (k + 2) % 3];
        }

    VertexCurvature out;
    out.mean.assign(nv, 0.0f);
    out.gaussian.assign(nv, 0.0f);
    out.shape_index.assign(nv, 0.0f);
    const double r2 = double(radius) * radius;
    // A few chunks per thread, each with its own visit stamps (one word per vertex: a vertex is
    // in the current neighbourhood when its stamp is the current vertex + 1).
    const std::size_t chunks = std::clamp<std::size_t>(nv / 4096, 1, 4 * thread_count());
    const std::size_t per_chunk = (nv + chunks - 1) / chunks;
    parallel_chunks(chunks, thread_count(), [&](std::size_t chunk) {
        std::vector<std::uint32_t> ring;
        std::vector<std::uint32_t> stamp(nv, 0);
        const std::size_t end = std::min(nv, (chunk + 1) * per_chunk);
        for (std::size_t v = chunk * per_chunk; v < end; ++v) {
            const std::uint32_t visit = static_cast<std::uint32_t>(v) + 1;
            const Vec3 p = vertex(mesh, v);
            const Vec3 n =
                unit({mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]});
            // Tangent frame (u, w, n).
            const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
            const Vec3 u = unit(cross(n, helper)), w = cross(n, u);
            // Neighbours by breadth-first search through the mesh, within `radius` of p.
            ring.assign(1, static_cast<std::uint32_t>(v));
            stamp[v] = visit;
            std::array<std::array<double, 6>, 5> a{};
            std::size_t used = 0;
            for (std::size_t head = 0; head < ring.size() && ring.size() < kMaxNeighbours; ++head) {
                const std::uint32_t q = ring[head];
                for (std::uint32_t k = count[q]; k < count[q + 1]; ++k) {
                    const std::uint32_t nb = adj[k];
                    if (stamp[nb] == visit) continue;
                    stamp[nb] = visit;  // near or far, looked at once
                    const Vec3 d0 = vertex(mesh, nb);
                    const Vec3 d{d0[0] - p[0], d0[1] - p[1], d0[2] - p[2]};
                    if (dot(d, d) > r2) continue;
                    ring.push_back(nb);
                    // h = c0 x² + c1 x y + c2 y² + c3 x + c4 y, least squares.
                    const double x = dot(d, u), y = dot(d, w), h = dot(d, n);
                    const double f[5] = {x * x, x * y, y * y, x, y};
                    for (int i = 0; i < 5; ++i) {
                        for (int j = 0; j < 5; ++j) a[i][j] += f[i] * f[j];
                        a[i][5] += f[i] * h;
                    }
                    ++used;
                }
            }
            std::array<double, 5> c{};
            if (used < 5 || !solve5(a, c)) continue;  // too few neighbours: 0
            const double fx = c[3], fy = c[4], fxx = 2 * c[0], fxy = c[1], fyy = 2 * c[2];
            const double g = 1.0 + fx * fx + fy * fy;
            const double K = (fxx * fyy - fxy * fxy) / (g * g);
            // The normal points out: a convex surface bends away from it (h < 0), so H > 0
            // needs the minus sign.
            const double H =
                -((1 + fy * fy) * fxx - 2 * fx * fy * fxy + (1 + fx * fx) * fyy) /
                (2 * std::pow(g, 1.5));
            const double disc = std::sqrt(std::max(H * H - K, 0.0));
            const double k1 = H + disc, k2 = H - disc;
            double S = 0.0;
            if (k1 - k2 > 1e-12)
                S = 2.0 / std::numbers::pi * std::atan((k1 + k2) / (k1 - k2));
            else if (H != 0.0)
                S = H > 0 ? 1.0 : -1.0;
            out.mean[v] = static_cast<float>(H);
            out.gaussian[v] = static_cast<float>(K);
            out.shape_index[v] = static_cast<float>(S);
        }
    });
    return out;
}

}  // namespace fdmsurf::detail
