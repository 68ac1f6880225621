// The --help text of the fdmsurf program: usage, every option with its unit and default, the
// exit codes (docs/cli.md says the same at more length).
#include "cli/usage.hpp"

namespace fdmsurf::cli {

std::string usage_text() {
    return R"(Usage: fdmsurf INPUT -o OUTPUT [options]
       fdmsurf INPUT [-o OUTPUT] --areas FILE.csv|FILE.json [options]
       fdmsurf INPUT --models all [-o FOLDER/] --areas FILE.csv|FILE.jsonl [options]
       fdmsurf INPUT... -o FOLDER/ [options]
       fdmsurf INPUT -o PICTURE.png [picture options]
       fdmsurf INPUT... --models all -o FOLDER/ [options]
       fdmsurf compare REFERENCE TESTED --spacing H [--stats json] [--outer]
       fdmsurf prepare [--device D] [--validation] [--quiet]
       fdmsurf --list-devices | --help | --version

Writes the molecular surface of INPUT (PDB, mmCIF, PQR, XYZR or XYZRN; .gz
accepted; - reads standard input) as a triangle mesh to OUTPUT (binary .ply,
.obj, .glb, binary .stl or .off, by its extension; - writes standard output),
computed on a Vulkan device with the Filtered Density Map method (Giard & Macq
2010), or as a picture (.png) drawn on that device. With several inputs, -o names a folder that gets one NAME.ply per input,
all computed in one process on one device. `fdmsurf compare` measures a mesh
against a reference mesh (weighted RMSD of Giard & Macq; see docs/compare.md).
`fdmsurf prepare` builds once what a small structure's first run would compile
(FFT plans of the grid sizes small grids are rounded to; see --natural-grid).
Options take their value as `--name value` or `--name=value`.

Surface:
  --surface ses|vdw|sas  solvent excluded (filtered density), van der Waals or
                         solvent accessible surface (default ses)
  --method fdm|edt       how the ses surface is computed: fdm, the filtered density
                         map (smooth, about 0.15-0.2 Å from the exact SES), or edt,
                         the exact SES (distance to where the probe's centre fits,
                         at level R; no filter, all cavities kept) (default fdm)
  --spacing H            grid spacing, Å (> 0, default 0.5)
  --probe R              solvent probe radius, Å (>= 0, default 1.4)
  --cutoff F             filter cut-off, 1/Å (>= 0; default 0: 1.3/(4 R) for the
                         Gaussian filter, 1/(4 R) for the ideal one); ses only
  --sigma S              Gaussian width σ of each atom's density, Å (> 0; for ses at least
                         r/√60 for the largest radius r; default 3)
  --level L              iso-level in units of T, the density on each atom's
                         van der Waals sphere (> 0; default 0.9 for ses with the
                         Gaussian filter, 1 otherwise)
  --filter ideal|gaussian  filter shape: the ideal spherical low-pass of the paper
                         or a Gaussian 2^-(|f|/F)^2 (default gaussian)
  --paper                the paper's settings: ideal filter at 1/(4 R), level 1,
                         all cavities kept (options given explicitly still apply)
  --no-cavities          keep only outer surfaces: remove every cavity
  --min-cavity-volume V  remove cavities enclosing less than V Å³ (>= 0; default:
                         for fdm, remove the cavities no probe sphere fits in; for
                         edt, vdw and sas keep all)
  --padding P            empty space around the atoms, Å (>= 0; default one filter
                         wavelength 1/F for fdm, 1 Å for edt, vdw and sas)
  --refine N             refine the mesh N times (0 to 4, default 0): each level
                         splits every triangle into four (modified butterfly) and
                         moves the new vertices onto the surface (the filtered
                         density for fdm, the exact SES for edt, the atoms'
                         spheres for vdw and sas)
  --no-snap              keep marching cubes' vertices where they are (default: on
                         the exact surface: for vdw and sas on the balls, with
                         vertices on the creases where spheres meet and chords
                         split to the chord tolerance; for edt projected onto the
                         exact SES)
  --chord-tolerance T    vdw and sas: split edges whose arc lies more than T Å
                         from them (>= 0; 0: none; default spacing / 50)
  --natural-grid         fdm: the smallest FFT-friendly grid (default: a small grid
                         is rounded up to a cube of 64 to 160 points whose FFT plan
                         `fdmsurf prepare` builds ahead, for a fast first run)

Input:
  --format pdb|cif|pqr|xyzr|xyzrn  input format (default: from the extension,
                         then the content; for - from the content)
  --model N              model to read, 1-based (default 1)
  --models all           every model, one mesh each: -o names a folder that gets
                         NAME-m1.ply, NAME-m2.ply, ... (one device for all)
  --assembly N           biological assembly N of a PDB or mmCIF file, the n-th
                         one it lists (REMARK 350 / _pdbx_struct_assembly), built
                         from the model before selection (default 0: the model
                         as deposited, i.e. the asymmetric unit)
  --waters               keep water molecules (default: left out)
  --hydrogens            keep hydrogen atoms (default: left out)
  --no-ligands           leave out HETATM residues other than water (default: kept)
  --chains A,B           keep only these chains (author chain ids, case-sensitive;
                         in an assembly the copies' names, A1, A2, ...); PDB,
                         mmCIF and PQR with chain ids
  --select EXPR          keep only the atoms that gemmi's selection EXPR matches,
                         after the rules above: /model/chain/residues/atoms[el]
                         with parts left out, e.g. 'A/10-50', '(HEM)', 'A/*/CA',
                         '[S]', ';b>20', ';polymer' (PDB, mmCIF and PQR)
  --patch EXPR           compute the surface of every atom read, then keep only
                         the triangles whose three vertices belong to atoms that
                         the selection EXPR matches: an open patch (a chain's
                         footprint in its complex, a binding site)

Colours and per-vertex properties (docs/properties.md):
  --color SCHEME         vertex colours: chain, element (CPK/Jmol), residue
                         (shapely), hydrophobicity (Kyte-Doolittle, blue-white-
                         orange), bfactor (blue-white-red), coulombic (red-white-
                         blue over -10..+10 kcal/(mol e)), #RRGGBB, or none
                         (default); PLY gets red green blue, OBJ v x y z r g b,
                         GLB COLOR_0, OFF r g b 255 (COFF); STL none
  --properties LIST      per-vertex scalars written as PLY float properties (GLB
                         _NAME attributes), from coulombic, hydrophobicity,
                         bfactor, mean_curvature, gaussian_curvature,
                         shape_index (comma-separated)
  Every PLY vertex also gets `uint atom` (GLB: float _ATOM): the index (0-based,
  in input order) of the atom it belongs to.

Mesh size and order (docs/mesh.md, "Simplification"):
  --simplify RATIO       keep about RATIO of the triangles (0 < RATIO <= 1), by
                         edge collapses in quadric-error order; the mesh keeps
                         its topology (closed, the same pieces and holes) and
                         every vertex keeps its atom, colour and properties;
                         the distance to the full mesh (Hausdorff, RMSD) is in
                         the summary
  --max-triangles N      simplify to at most about N triangles (N >= 1); with
                         --simplify too, the smaller of the two targets
  --simplifier NAME      collapse (default: fdmsurf's collapses, each tested so
                         that it keeps the topology) or meshopt (meshoptimizer's
                         meshopt_simplify; where it breaks the mesh, the surface
                         around is kept as it was and the rest redone)
  --optimize             reorder triangles and vertices for the GPU's vertex
                         cache and fetch (the same triangles); after --simplify

Device:
  --device INDEX|NAME    Vulkan device: an index from --list-devices or part of
                         its name (default: the first usable one, discrete first)
  --list-devices         list the Vulkan devices, whether each is usable and why
                         not, then exit (no INPUT needed)
  --validation           enable the Vulkan validation layer; any message it
                         reports makes the run fail (exit code 5, no output)
  --host-filter auto|on|off  the Gaussian filter as a separable convolution on
                         the host (the same low-pass) instead of VkFFT, for
                         grids in slabs and grids whose marching cubes runs on
                         the host: auto (default) does so when the device is a
                         CPU (lavapipe), where the FFTs share the host's cores
  --host-density auto|on|off  the density computed on the host's threads (the
                         same values to the exponential's rounding) instead of
                         the device's pass, where the filter (if any) and
                         marching cubes run on the host: auto (default) does so
                         when the device is a CPU (lavapipe)
  --host-mc auto|on|off  marching cubes on the host's threads (the same mesh)
                         instead of the device's passes: auto (default) does so
                         when the device is a CPU (lavapipe)
  --host-atoms auto|on|off  each vertex's atom searched on the host's threads
                         (the same atoms) instead of the device's pass: auto
                         (default) does so when the device is a CPU (lavapipe)
  --host-ses auto|on|off  the exact SES field (--method edt) computed on the
                         host's threads (each ball and arc scattered over the
                         points it reaches; the same values to float rounding)
                         instead of the device's pass: auto (default) does so
                         when the device is a CPU (lavapipe)

Output:
  -o, --output OUTPUT    the mesh file to write: .ply (binary), .obj, .glb
                         (glTF 2.0 binary: positions, normals, COLOR_0, _ATOM and
                         one _NAME per property), .stl (binary; positions only)
                         or .off (COFF when coloured), or a picture, .png (below);
                         - writes the mesh to standard output, and the summary
                         goes to stderr
  --output-format ply|obj|glb|stl|off|png  the format of OUTPUT, whatever its
                         extension (default: the extension; ply for -o -)
  --stats json|text      summary on stdout (stderr with -o -) as one JSON object
                         or as text (default text)
  --quiet                no text summary (warnings still go to stderr; --stats
                         json still prints its JSON)
  -h, --help             print this help and exit
  --version              print the version and exit

Areas (docs/areas.md):
  --areas FILE           write the area of the surface per atom, per residue
                         (chain, number, insertion code, name) and in total to
                         FILE, as .csv or .json by its extension. vdw and sas:
                         the exact area of each atom's sphere patch (sas: the
                         SASA), beside the written mesh's own area split by
                         sphere patch; ses: the mesh's area split by the atom
                         of each vertex. Without -o: no mesh, no device (vdw
                         and sas only). With --models all: one table of the
                         models (.csv or .jsonl), a row each: model, atoms,
                         area, volume, pieces, cavities, cavity volume (with
                         -o), exact SASA (--probe) in total and per chain
  --relative TABLE       add each residue's area relative to its maximum in a
                         published table: tien2013 (Tien et al. 2013,
                         theoretical), miller1987 or sander1994 (with --areas)
  --buried G1:G2         the buried interface area between two groups of atoms,
                         each a list of chain ids (A:B, A,C:B,D) or a gemmi
                         selection ('A/1-50:B'): each group's surface alone
                         against their complex, whose surface is the one
                         written (atoms in neither group are left out); per
                         atom, per residue and in total (with --areas)
Pictures (docs/rendering.md):
  -o FILE.png            the picture alone: the mesh stays on the device and is
                         drawn there by a Vulkan graphics pipeline (also
                         --output-format png; -o - writes the PNG to standard
                         output); with --simplify, --patch, --optimize,
                         --properties or --color coulombic the mesh is made on the
                         host first, then drawn
  --image FILE.png       a picture of the mesh written by -o, beside it (a folder,
                         ending in '/', with several inputs: NAME.png)
  --image-size WxH       picture size in pixels (default 1024x768; at most the
                         device's maxImageDimension2D)
  --view V[,V...]        front (from +z, the default), back, left (from -x),
                         right, top (from +y) or bottom; several: one PNG each,
                         NAME-VIEW.png (also --views)
  --rotate X,Y,Z         turn the molecule by these degrees about the screen's x
                         (right), y (up) and z axes, in that order, after the view
  --background C         #RRGGBB, white (the default), black or transparent
  --outline              dark lines along silhouettes and depth steps
  --occlusion S          ambient occlusion strength, 0 (off) to 1 (default 0.8)
  --depth-cue S          darkening of the far side, 0 (off) to 1 (default 0.35)
  The camera is orthographic, fitted to the mesh's bounding sphere; colours come
  from --color (uniform light grey without it).

Exit codes:
  0  success
  1  unexpected failure (a bug in fdmsurf)
  2  invalid command line or option value, unknown output extension (or
     --areas extension), a picture size above the device's
     maxImageDimension2D, --buried groups that name a missing chain, select
     no atom or overlap, --relative or --buried on input without residues
  3  input or output error: unreadable or malformed structure, no atoms
     selected, output file or folder not writable, standard output closed
     (a broken pipe)
  4  device error: no usable Vulkan device (on a machine without a GPU install
     mesa-vulkan-drivers), job too large for the device, Vulkan or VkFFT failure
  5  --validation: the Vulkan validation layer reported messages
  6  the Vulkan device was lost (driver reset, GPU fault or removal)
  7  out of memory: a device or host allocation failed
)";
}

}  // namespace fdmsurf::cli
