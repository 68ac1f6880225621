// The surface pipeline: atoms in, triangle mesh out, through Vulkan compute (Giard & Macq 2010).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/properties.hpp"
#include "fdmsurf/structure.hpp"

namespace fdmsurf {

struct ExternalDevice;       // fdmsurf/vulkan_interop.hpp
struct DeviceSurfaceResult;  // fdmsurf/vulkan_interop.hpp
class DeviceMesh;            // fdmsurf/vulkan_interop.hpp

enum class SurfaceKind {
    Ses,  // solvent excluded: filtered density (FDM)
    Vdw,  // van der Waals: union of atom balls, no filter
    Sas,  // solvent accessible: union of balls of radius r + probe, no filter
};

// How the ses surface is computed.
enum class SesMethod {
    Fdm,  // the filtered density map (Giard & Macq 2010): smooth, about 0.15-0.2 Å from the SES
    Edt,  // exact: the level set r_s of the distance to where a probe centre fits (the closing of
          // the atoms by the probe), evaluated from the SAS's spheres and arcs at every grid point
};

enum class FilterShape {
    Ideal,     // the paper's spherical mask: keep |f| <= cutoff
    Gaussian,  // H(f) = 2^-(|f| / cutoff)^2
};

struct SurfaceOptions {
    SurfaceKind surface = SurfaceKind::Ses;
    SesMethod method = SesMethod::Fdm;  // ses only; Edt needs probe > 0 and ignores the filter,
                                        // cut-off, sigma, level and density_cut
    float spacing = 0.5f;   // grid spacing h, Å (> 0)
    float probe = 1.4f;     // solvent probe radius r_s, Å (>= 0)
    float cutoff = 0.0f;    // filter cut-off f_c, 1/Å; 0: 1.3 / (4 probe) for the Gaussian
                            // filter, 1 / (4 probe) for the ideal one (the paper's)
    float sigma = 3.0f;     // Gaussian width σ, Å (> 0)
    // Iso-level as a multiple of T (the density is T on each vdW sphere); 0: 0.9 for ses with
    // the Gaussian filter, 1 otherwise (vdw and sas are exact at 1).
    float level = 0.0f;
    // Defaults of the filter and level: measured against the analytical SES (docs/accuracy.md);
    // paper_settings() gives the paper's (ideal mask at 1/(4 probe), level 1).
    FilterShape filter = FilterShape::Gaussian;
    float padding = -1.0f;  // empty space around the Gaussian support, Å; < 0: one filter
                            // wavelength (1/f_c) for ses, 1 Å otherwise
    float density_cut = 1e-2f;  // G_i is taken as 0 where it falls below density_cut * T
    // Cavities (closed inward-facing pieces) enclosing less than this volume (Å³) are removed.
    // < 0 (the default): for ses with the FDM method, every cavity in which no probe sphere fits
    // between the atoms (a void that is not part of the SES, whatever its volume); nothing for
    // the exact SES (Edt), vdw and sas. Infinity removes every cavity.
    float min_cavity_volume = -1.0f;
    // Refinement levels (0 to 4): each level splits every triangle into four by modified
    // butterfly subdivision (Zorin et al. 1996) and moves the new vertices onto the iso-surface
    // of the field (ses) or onto the atoms' balls (vdw, sas); on the host, before cavity removal.
    int refine = 0;
    // Place the mesh on the exact surface after marching cubes (docs/mesh.md, "Snapping"); on
    // the host, after refinement for vdw and sas, before it for edt. vdw and sas: every vertex on
    // its ball, edges split where they cross the circles on which two spheres meet (the creases)
    // and triangles at the points where three meet, and chords split until each lies within
    // chord_tolerance of its arc. ses with SesMethod::Edt: every vertex projected onto the exact
    // SES distance (Newton along its normal, else its gradient). Ignored by the FDM method, whose
    // field has no exact surface to snap to.
    bool snap = true;
    // vdw and sas with snap: the most an edge's arc may lie from the edge (sagitta), Å; longer
    // edges are split. < 0: spacing / 50 (0.01 Å at 0.5 Å); 0: no chord splits.
    float chord_tolerance = -1.0f;
    // Grid points per axis at least (0: as many as the atoms need). A batch of similar
    // structures (the models of an NMR ensemble) given the largest grid of the batch shares one
    // FFT plan and one set of compiled kernels (plan_surface_grid gives each one's grid).
    std::array<std::uint32_t, 3> min_grid{0, 0, 0};
    // FDM with the Gaussian filter (the default) only: round a small grid up to one of a few
    // cube sizes (64 to 160 points a side; not when that would more than 2.5-fold its points
    // beyond 96^3), adding points around it on its own lattice, so that its FFT plan is one
    // that Engine::prepare (`fdmsurf prepare`) built ahead and a first run does not compile FFT
    // kernels (docs/performance.md, "Cold start"). The mesh moves by less than 1e-3 Å (2e-5 Å
    // on 1CRN). The ideal filter (paper_settings) keeps its grid: its mask, sampled on the
    // box's frequencies, would change. false: the smallest FFT-friendly grid.
    bool canonical_grid = true;
    // Colours and per-vertex scalars (Mesh::colors, Mesh::scalars). Mesh::atoms is always set.
    PropertyOptions properties;
    // Also give SurfaceResult::stats: the mesh's statistics, found with the pieces the cavity
    // removal finds anyway (one analysis of the mesh for both), cheaper than compute_stats after.
    bool mesh_stats = false;
};

// The settings of Giard & Macq (2010): ideal mask at f_c = 1/(4 probe), level T, cavities kept.
SurfaceOptions paper_settings(SurfaceOptions options = {});

// Where the grid sits: point (i, j, k) is at origin + h * (i, j, k).
struct GridInfo {
    std::array<float, 3> origin{};
    float spacing = 0.0f;
    std::array<std::uint32_t, 3> dims{};  // points along x, y, z
    std::uint32_t slabs = 1;              // > 1 when processed in overlapping parts
    bool host_filter = false;             // the Gaussian filter ran on the host
    bool host_density = false;            // the density was computed on the host
    bool host_marching_cubes = false;     // marching cubes ran on the host
    bool host_ses_distance = false;       // the exact SES field was computed on the host
    float cutoff = 0.0f;                  // filter cut-off used (1/Å), 0 for vdw, sas and edt
};

struct StageTime {
    std::string name;  // "density", "fft-forward", ...
    double ms = 0.0;
    bool gpu = false;  // measured with GPU timestamps (else host clock)
};

struct SurfaceResult {
    Mesh mesh;
    GridInfo grid;
    std::vector<StageTime> times;
    std::vector<std::string> warnings;
    std::size_t cavities_removed = 0;  // pieces removed by SurfaceOptions::min_cavity_volume
    std::size_t specks_removed = 0;    // edt: closed pieces enclosing less than one grid cell
    // With SurfaceOptions::mesh_stats: compute_stats(mesh), bit for bit; otherwise empty.
    std::optional<MeshStats> stats;
};

struct DeviceInfo {
    std::uint32_t index = 0;
    std::string name;
    std::string type;          // "discrete GPU", "CPU", ...
    std::string driver;        // driver name and version
    std::string api_version;   // "1.3.230"
    bool usable = false;
    std::string reason;        // why it is not usable, when usable is false
    std::uint64_t max_storage_buffer_range = 0;
    std::uint64_t device_memory = 0;  // bytes in the largest device-local heap
};

// Called on the calling thread as each stage of make_surface ends, with the stage's name
// ("bin-atoms", "density, filter, marching cubes", "field slab 2/5", "cavities", ...), for a
// progress display. An exception it throws ends make_surface with that exception.
using ProgressCallback = std::function<void(std::string_view stage)>;

// Where a stage runs when the host can run it instead of the device
// (EngineOptions::gaussian_filter, marching_cubes, vertex_atoms, ses_distance).
enum class StagePlace {
    Auto,    // the host when the device is a CPU implementation (lavapipe), else the device
    Device,  // the device's compute passes
    Host,    // the host's threads
};
using GaussianFilterPlace = StagePlace;

struct EngineOptions {
    // Device: empty = the first usable one (discrete GPU first); a number = that index; else a
    // case-insensitive substring of the device name.
    std::string device;
    // Enable VK_LAYER_KHRONOS_validation and collect its messages (validation_messages()).
    bool validation = false;
    // Override of maxStorageBufferRange, bytes; 0 = the device's. Tests lower it to force the
    // processing of a grid in slabs.
    std::uint64_t max_buffer_range = 0;
    // Run on the application's own VkDevice (fdmsurf/vulkan_interop.hpp) instead of creating
    // one; `device` and `validation` are then ignored. Not owned; must outlive the Engine.
    const ExternalDevice* external = nullptr;
    ProgressCallback progress;  // empty: none
    // The Gaussian filter of grids in slabs, and of a grid in one binding whose marching cubes
    // runs on the host (the ideal filter always goes through VkFFT). On the host: a separable
    // convolution in space, the same low-pass. On a CPU device the FFTs share the host's cores
    // with everything else, and three passes of a kernel of 2 ceil(6 sigma) + 1 taps (21 at the
    // defaults) cost a fraction of them (docs/performance.md). Below 1.5 grid points of sigma
    // (spacings above 0.54 Å at the default cut-off) the sampled kernel's aliases make it a
    // slightly different low-pass (up to exp(-pi^2 sigma^2 / 2) of the mask at the Nyquist
    // frequency: 0.04 at 1 Å), as close to the analytical SES (docs/accuracy.md).
    GaussianFilterPlace gaussian_filter = GaussianFilterPlace::Auto;
    // The density of fdm, vdw and sas surfaces, where the rest of the field's stages run on the
    // host (the Gaussian filter of a filtered surface, and marching cubes): the shader's
    // candidate rule and power expression on all threads, box by box, skipping the boxes no
    // atom reaches; the same values but for the exponential's rounding. On a CPU device it
    // costs a fraction of the compute pass (docs/performance.md).
    StagePlace density = StagePlace::Auto;
    // Marching cubes (not for make_device_surface's mesh, left on the device). On the host it
    // walks rows of inside bits packed 64 to a word on all threads and reads the slabs' planes
    // where they already are (no upload, no read-back, no unpacking); a grid in one binding
    // comes back after the density (or the exact SES's pass). On a CPU device it costs a
    // fraction of the compute passes (docs/performance.md). The mesh is the CPU reference's bit
    // for bit, which the device's passes match to float rounding.
    StagePlace marching_cubes = StagePlace::Auto;
    // The search for each vertex's atom of a mesh on the host (make_device_surface's mesh keeps
    // the device's pass): on the host the shader's search in C++ on all threads, the same atoms
    // (docs/performance.md).
    StagePlace vertex_atoms = StagePlace::Auto;
    // The exact SES field (--method edt; make_device_surface's mesh in one binding keeps the
    // device's pass, in slabs its mesh goes through the host anyway). On the host each
    // ball and each exposed arc is scattered over the grid points it can be nearest to, on all
    // threads, instead of the device's per-point gather of every candidate: on a CPU device a
    // fraction of the pass's time (docs/performance.md). The same values to float rounding
    // (within 5e-5 Å of the CPU reference, as the device's pass).
    StagePlace ses_distance = StagePlace::Auto;
};

namespace detail { struct EngineImpl; }

// Owns the Vulkan instance, device, pipelines and FFT plans; reuse it for many surfaces.
// Not thread-safe: one make_surface at a time.
class Engine {
public:
    explicit Engine(const EngineOptions& options = {});
    ~Engine();
    Engine(Engine&&) noexcept;
    Engine& operator=(Engine&&) noexcept;
    Engine(const Engine&) = delete;
    Engine& operator=(const Engine&) = delete;

    // Throws Error (InvalidArgument, EmptySelection, DeviceLimit, Vulkan, Fft).
    SurfaceResult make_surface(const Atoms& atoms, const SurfaceOptions& options = {});

    // The same surface, left on the device for a renderer (fdmsurf/vulkan_interop.hpp). Small
    // cavities are not removed on this path (that needs the mesh on the host). With refine > 0
    // the mesh is read back, refined on the host and uploaded. With a colour scheme in
    // options.properties.color, each vertex's atom and colour are found on the device from the
    // mesh's own vertex buffer (DeviceMesh::attribute_buffer; stage "vertex-atoms"); the
    // Coulombic colours and per-vertex scalars need the host mesh (Error InvalidArgument: use
    // make_surface and upload_mesh).
    DeviceSurfaceResult make_device_surface(const Atoms& atoms, const SurfaceOptions& options = {});

    // A host mesh copied into device buffers laid out as make_device_surface's (positions and
    // normals interleaved, indices, and, when the mesh has colors, atoms and colours): for
    // drawing a mesh that was simplified, cut into a patch or read from a file. Normals are
    // computed from the triangles when the mesh has none. Throws Error(InvalidArgument) for
    // arrays of inconsistent sizes or an index out of range.
    DeviceMesh upload_mesh(const Mesh& mesh);

    // Builds ahead what a first surface on a small grid would build: the FFT plans of the
    // canonical grid sizes (SurfaceOptions::canonical_grid), stored in fdmsurf's plan cache,
    // and the driver's machine code for them and for the engine's kernels, which Mesa keeps in
    // its shader cache (lavapipe compiles a kernel at its first dispatch: every plan and every
    // stage of the default fdm, edt, vdw and sas surfaces is run once, on one atom; not the
    // Coulombic colours' kernel nor the PNG renderer's). Run once per machine, device and
    // driver (`fdmsurf prepare`; scripts/setup-debian.sh does), it makes the first run of a
    // small structure in a new process about as fast as a later one (docs/performance.md,
    // "Cold start"). One row per plan: its grid, whether the plan cache had it, milliseconds
    // (plan and surface).
    struct PreparedPlan {
        std::array<std::uint32_t, 3> dims{};
        bool from_cache = false;  // read from the plan cache
        bool stored = false;      // built and written to it (false: the cache is off or its
                                  // folder cannot be written)
        double ms = 0.0;
    };
    std::vector<PreparedPlan> prepare();

    const DeviceInfo& device() const;
    // Validation-layer messages (warnings and errors) seen since the last call; cleared by it.
    std::vector<std::string> take_validation_messages();

    detail::EngineImpl& impl() { return *impl_; }

private:
    std::unique_ptr<detail::EngineImpl> impl_;
};

// All physical devices with the reason each is or is not usable. Throws Error(NoDevice) when
// the Vulkan loader or any driver is missing.
std::vector<DeviceInfo> list_devices();

// The grid make_surface would use for `atoms` (no device work); throws as make_surface does
// for invalid options or atoms.
GridInfo plan_surface_grid(const Atoms& atoms, const SurfaceOptions& options = {});

// Checks options and returns the effective cut-off (1/Å); throws Error(InvalidArgument).
float effective_cutoff(const SurfaceOptions& options);
// The iso-level (multiple of T) that `options` selects.
float effective_level(const SurfaceOptions& options);

const char* to_string(SurfaceKind kind) noexcept;
const char* to_string(SesMethod method) noexcept;

}  // namespace fdmsurf
