// Per-atom and per-residue areas of a surface: exact sphere patches for vdw and sas, the mesh
// split by sphere patch or vertex atom, and the published maxima of relative SASA.
#include <cmath>
#include <string>
#include <unordered_map>

#include "areas/areas_detail.hpp"
#include "fdmsurf/areas.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf {

namespace detail {

BallParameters ball_parameters(const SurfaceOptions& options) {
    BallParameters b;
    b.radius_add = options.surface == SurfaceKind::Sas ? options.probe : 0.0;
    // The vdw and sas field is T exp(−π/σ²) (π the power distance, T = 1): the level L is the
    // power distance π_iso = −σ² ln L, the balls of radius sqrt((r + add)² + π_iso); 0 at the
    // default level 1 (src/engine/snap_stage.cpp).
    const double sigma2 = double(options.sigma) * options.sigma;
    b.pi_iso = -sigma2 * std::log(double(effective_level(options)));
    return b;
}

}  // namespace detail

AtomAreas surface_atom_areas(const Atoms& atoms, const SurfaceOptions& options, const Mesh* mesh) {
    AtomAreas out;
    const bool balls = options.surface != SurfaceKind::Ses;
    if (!balls && mesh == nullptr)
        throw Error(ErrorCode::InvalidArgument,
                    "areas: the ses areas come from the mesh (no closed form): compute the "
                    "surface first");
    if (balls) {
        const detail::BallParameters b = detail::ball_parameters(options);
        if (!std::isfinite(b.pi_iso))
            throw Error(ErrorCode::InvalidArgument, "areas: the iso-level must be > 0");
        out.area = detail::exact_ball_areas(atoms, b.radius_add, b.pi_iso);
        out.exact = true;
        if (mesh != nullptr)
            // 2e-4 Å: the snap stage places vertices in double precision and stores floats
            // (1.5e-5 Å apart at 200 Å from the origin).
            out.mesh_area = detail::mesh_patch_areas(*mesh, atoms, b, 2e-4, &out.mesh_on_patches);
    } else {
        out.mesh_area = atom_mesh_areas(*mesh, atoms.size());
        out.area = out.mesh_area;
    }
    return out;
}

namespace {

// The 20 amino acids in alphabetical order of their three-letter codes.
constexpr const char* kAminoAcids[20] = {"ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU",
                                         "GLY", "HIS", "ILE", "LEU", "LYS", "MET", "PHE",
                                         "PRO", "SER", "THR", "TRP", "TYR", "VAL"};
// Å², in the order of kAminoAcids. Tien et al. 2013: "theoretical" maxima (Gly-X-Gly tripeptides
// in any allowed conformation). Miller et al. 1987: Gly-X-Gly, extended. Sander & Rost 1994:
// the values DSSP's users divide by.
constexpr double kTien2013[20] = {129, 274, 195, 193, 167, 225, 223, 104, 224, 197,
                                  201, 236, 224, 240, 159, 155, 172, 285, 263, 174};
constexpr double kMiller1987[20] = {113, 241, 158, 151, 140, 189, 183, 85,  194, 182,
                                    180, 211, 204, 218, 143, 122, 146, 259, 229, 160};
constexpr double kSander1994[20] = {106, 248, 157, 163, 135, 198, 194, 84,  184, 169,
                                    164, 205, 188, 197, 136, 130, 142, 227, 222, 142};

}  // namespace

double residue_max_area(std::string_view name, RelativeTable table) {
    const double* values = table == RelativeTable::Tien2013     ? kTien2013
                           : table == RelativeTable::Miller1987 ? kMiller1987
                           : table == RelativeTable::Sander1994 ? kSander1994
                                                                : nullptr;
    if (values == nullptr) return -1.0;
    for (int k = 0; k < 20; ++k)
        if (name == kAminoAcids[k]) return values[k];
    return -1.0;
}

const char* to_string(RelativeTable table) noexcept {
    switch (table) {
        case RelativeTable::Tien2013:
            return "tien2013";
        case RelativeTable::Miller1987:
            return "miller1987";
        case RelativeTable::Sander1994:
            return "sander1994";
        case RelativeTable::None:
            break;
    }
    return "none";
}

std::vector<ResidueArea> residue_areas(const Atoms& atoms, const AtomAreas& areas,
                                       RelativeTable table) {
    if (!atoms.has_residues())
        throw Error(ErrorCode::InvalidArgument,
                    "per-residue areas need residues: the atoms have none (XYZR input has only "
                    "coordinates and radii, XYZRN names residues only in MSMS's "
                    "chain_number_icode_residue_atom form; give PDB, mmCIF, PQR or XYZRN)");
    if (areas.area.size() != atoms.size() ||
        (!areas.mesh_area.empty() && areas.mesh_area.size() != atoms.size()))
        throw Error(ErrorCode::InvalidArgument, "residue_areas: one area per atom needed");
    std::vector<ResidueArea> out;
    std::unordered_map<std::string, std::size_t> index;
    std::string key;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const AtomMeta& m = atoms.meta[i];
        if (!m.in_residue) continue;  // an XYZRN name of another form than MSMS's
        key = m.chain;
        key += '\x1f';
        key += std::to_string(m.residue_number);
        key += m.insertion_code;
        key += '\x1f';
        key += m.residue_name;
        auto [it, inserted] = index.try_emplace(key, out.size());
        if (inserted) {
            ResidueArea r;
            r.chain = m.chain;
            r.number = m.residue_number;
            r.insertion_code = m.insertion_code;
            r.name = m.residue_name;
            r.max_area = residue_max_area(m.residue_name, table);
            out.push_back(std::move(r));
        }
        ResidueArea& r = out[it->second];
        r.atoms.push_back(std::uint32_t(i));
        r.area += areas.area[i];
        if (!areas.mesh_area.empty()) r.mesh_area += areas.mesh_area[i];
    }
    for (ResidueArea& r : out)
        if (r.max_area > 0.0) r.relative = r.area / r.max_area;
    return out;
}

}  // namespace fdmsurf
