// MSMS's .vert, .face and .area files, and the SES part of each vertex.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "base/text.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/msms.hpp"
#include "io/atomic_file.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {

namespace {

[[noreturn]] void invalid(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, message);
}

// The XYZRN name of atom i, or "" when the atoms carry none.
const std::string& name_of(const Atoms& atoms, std::size_t i) {
    static const std::string none;
    return atoms.meta.size() == atoms.size() ? atoms.meta[i].xyzrn_name : none;
}

// Text lines into an AtomicFile through one reusable buffer.
class LineWriter {
public:
    explicit LineWriter(const std::string& path) : file_(path) {}
    template <class... Args>
    void line(const char* format, Args... args) {
        char buf[256];
        const int n = std::snprintf(buf, sizeof buf, format, args...);
        text_.append(buf, std::size_t(std::clamp(n, 0, int(sizeof buf) - 1)));
        if (text_.size() > (1u << 20)) drain();
    }
    void text(const std::string& s) { text_ += s; }
    void drain() {
        file_.write(text_);
        text_.clear();
    }
    void commit() {
        drain();
        file_.commit();
    }

private:
    detail::AtomicFile file_;
    std::string text_;
};

void count_line(LineWriter& w, std::size_t count, const Atoms& atoms,
                const MsmsFileOptions& o) {
    w.line("%7zu %7zu %6.2f %6.2f\n", count, atoms.size(), double(o.density), double(o.probe));
}

}  // namespace

std::vector<SesPart> ses_vertex_parts(const Mesh& mesh, const Atoms& atoms, float probe,
                                      float tolerance) {
    const std::size_t nv = mesh.vertex_count();
    if (!(probe > 0.0f) || !(tolerance >= 0.0f))
        invalid("ses_vertex_parts: needs probe > 0 and tolerance >= 0");
    if (nv > 0 && (mesh.atoms.size() != nv || mesh.normals.size() != 3 * nv))
        invalid("ses_vertex_parts: the mesh needs per-vertex atoms and normals");
    std::vector<SesPart> parts(nv, SesPart::Contact);
    if (nv == 0) return parts;
    double rmax = 0.0;
    for (float r : atoms.radius) rmax = std::max(rmax, double(r));
    const double reach = rmax + probe + tolerance;
    const detail::CellList cells = detail::make_cell_list(atoms.xyz, reach);
    const std::size_t chunk = 4096;
    detail::parallel_chunks((nv + chunk - 1) / chunk, detail::thread_count(), [&](std::size_t c) {
        for (std::size_t v = c * chunk; v < std::min(nv, (c + 1) * chunk); ++v) {
            const std::uint32_t a = mesh.atoms[v];
            if (a >= atoms.size()) invalid("ses_vertex_parts: vertex atom out of range");
            double p[3], d2 = 0.0;
            for (int k = 0; k < 3; ++k) {
                p[k] = mesh.positions[3 * v + k];
                const double d = p[k] - atoms.xyz[3 * a + k];
                d2 += d * d;
            }
            if (std::abs(std::sqrt(d2) - atoms.radius[a]) <= tolerance) continue;  // contact
            double q[3];
            for (int k = 0; k < 3; ++k) q[k] = p[k] + double(probe) * mesh.normals[3 * v + k];
            int touched = 0;
            cells.for_each_near(q, [&](std::uint32_t j) {
                const double r = double(atoms.radius[j]) + probe + tolerance;
                double e2 = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double d = q[k] - atoms.xyz[3 * j + k];
                    e2 += d * d;
                }
                touched += e2 < r * r ? 1 : 0;
            });
            parts[v] = touched >= 3 ? SesPart::Reentrant : SesPart::Toric;
        }
    });
    return parts;
}

std::vector<Mesh> msms_components(const Mesh& mesh) {
    const std::size_t nv = mesh.vertex_count(), nt = mesh.triangle_count();
    for (std::uint32_t i : mesh.indices)
        if (i >= nv) invalid("msms_components: vertex index out of range");
    detail::DisjointSets sets(nv);
    for (std::size_t t = 0; t < nt; ++t) {
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 1]);
        sets.unite(mesh.indices[3 * t], mesh.indices[3 * t + 2]);
    }
    // Signed volume per piece (divergence theorem), by root.
    std::vector<double> volume(nv, 0.0);
    const std::vector<float>& p = mesh.positions;
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t* i = &mesh.indices[3 * t];
        const float* a = &p[3 * i[0]];
        const float* b = &p[3 * i[1]];
        const float* c = &p[3 * i[2]];
        volume[sets.find(i[0])] +=
            (double(a[0]) * (double(b[1]) * c[2] - double(b[2]) * c[1]) -
             double(a[1]) * (double(b[0]) * c[2] - double(b[2]) * c[0]) +
             double(a[2]) * (double(b[0]) * c[1] - double(b[1]) * c[0])) /
            6.0;
    }
    // Component of each root: 0 for the outer pieces, then cavities by enclosed volume.
    std::vector<std::uint32_t> cavities;
    for (std::uint32_t v = 0; v < nv; ++v)
        if (sets.find(v) == v && volume[v] < 0.0) cavities.push_back(v);
    std::stable_sort(cavities.begin(), cavities.end(),
                     [&](std::uint32_t x, std::uint32_t y) { return volume[x] < volume[y]; });
    std::vector<std::uint32_t> component(nv, 0);
    for (std::size_t k = 0; k < cavities.size(); ++k) component[cavities[k]] = std::uint32_t(k + 1);
    std::vector<Mesh> out(cavities.size() + 1);
    std::vector<std::vector<std::uint32_t>> kept(out.size());
    std::vector<std::uint32_t> remap(nv, 0);
    for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t c = component[sets.find(v)];
        remap[v] = std::uint32_t(kept[c].size());
        kept[c].push_back(v);
    }
    for (std::size_t t = 0; t < nt; ++t) {
        const std::uint32_t c = component[sets.find(mesh.indices[3 * t])];
        for (int k = 0; k < 3; ++k) out[c].indices.push_back(remap[mesh.indices[3 * t + k]]);
    }
    for (std::size_t c = 0; c < out.size(); ++c) detail::copy_vertices(mesh, out[c], kept[c]);
    return out;
}

void write_msms_surface(const Mesh& mesh, const Atoms& atoms, const std::vector<SesPart>& parts,
                        const std::string& base, const MsmsFileOptions& o) {
    const std::size_t nv = mesh.vertex_count();
    if (nv > 0 && (mesh.atoms.size() != nv || mesh.normals.size() != 3 * nv))
        invalid("write_msms_surface: the mesh needs per-vertex atoms and normals");
    if (parts.size() != nv) invalid("write_msms_surface: one part per vertex needed");
    for (std::uint32_t a : mesh.atoms)
        if (a >= atoms.size()) invalid("write_msms_surface: vertex atom out of range");
    for (std::uint32_t i : mesh.indices)
        if (i >= nv) invalid("write_msms_surface: vertex index out of range");
    const bool names = atoms.meta.size() == atoms.size();

    LineWriter vert(base + ".vert");
    if (o.header) {
        vert.text("# MSMS solvent excluded surface vertices for " + detail::printable(o.source) +
                  " (written by fdmsurf)\n");
        vert.text("#vertex #sphere density probe_r\n");
        count_line(vert, nv, atoms, o);
    }
    for (std::size_t v = 0; v < nv; ++v) {
        const float* p = &mesh.positions[3 * v];
        const float* n = &mesh.normals[3 * v];
        const std::uint32_t a = mesh.atoms[v];
        vert.line("%9.3f %9.3f %9.3f %9.3f %9.3f %9.3f %7d %7u %2d", double(p[0]), double(p[1]),
                  double(p[2]), double(n[0]), double(n[1]), double(n[2]), 0, a + 1,
                  int(parts[v]));
        if (names && !atoms.meta[a].xyzrn_name.empty()) vert.text(" " + atoms.meta[a].xyzrn_name);
        vert.text("\n");
    }

    LineWriter face(base + ".face");
    if (o.header) {
        face.text("# MSMS solvent excluded surface triangles for " + detail::printable(o.source) +
                  " (written by fdmsurf)\n");
        face.text("#faces  #sphere density probe_r\n");
        count_line(face, mesh.triangle_count(), atoms, o);
    }
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* i = &mesh.indices[3 * t];
        const SesPart a = parts[i[0]], b = parts[i[1]], c = parts[i[2]];
        const SesPart type = a == b || a == c ? a : b == c ? b : SesPart::Toric;
        face.line("%6u %6u %6u %2d %6d\n", i[0] + 1, i[1] + 1, i[2] + 1, int(type), 0);
    }
    // Both complete before either is renamed into place.
    vert.drain();
    face.drain();
    vert.commit();
    face.commit();
}

void write_msms_areas(const Atoms& atoms, const std::vector<double>& ses,
                      const std::vector<double>& sas, const std::string& path,
                      const MsmsFileOptions& o) {
    if (ses.size() != atoms.size() || sas.size() != atoms.size())
        invalid("write_msms_areas: one SES and one SAS area per atom needed");
    LineWriter area(path);
    if (o.header) area.text("    Atom     Ses_A     Sas_A\n");
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        area.line("%8zu %9.3f %9.3f", i + 1, ses[i], sas[i]);
        const std::string& name = name_of(atoms, i);
        if (!name.empty()) area.text(" " + name);
        area.text("\n");
    }
    area.commit();
}

}  // namespace fdmsurf
