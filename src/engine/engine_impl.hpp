// The engine's internals: the Vulkan objects and stage passes it owns, and hooks for the tests
// that compare each GPU stage with its CPU reference.
#pragma once

#include <memory>
#include <vector>

#include "fdmsurf/surface.hpp"
#include "fdmsurf/vulkan_interop.hpp"
#include "filter/spectral_filter.hpp"
#include "grid/atom_bins.hpp"
#include "grid/density_gpu.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_gpu.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "isosurface/marching_cubes_gpu.hpp"
#include "properties/vertex_properties_gpu.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf::detail {

// What a DeviceMesh owns.
struct DeviceMeshBuffers {
    GpuMesh mesh;
    Buffer attributes;  // per vertex: atom, packed colour; empty when uncoloured
};

// Whether the snap stage changes the mesh of `options` (snap on, a field with an exact
// surface: vdw, sas, edt), and the chord tolerance it uses for vdw and sas (Å).
bool snaps(const SurfaceOptions& options, const GridPlan& plan);
double chord_tolerance_for(const SurfaceOptions& options);

// What the field of a one-piece surface is made from (EngineImpl::find_field_sources): the
// atoms binned on the grid (fdm, vdw, sas) or the exact SES's features and their host index,
// and where the field is computed and marched.
struct FieldSources {
    AtomBins bins;
    SesFeatures features;
    std::unique_ptr<SesHostField> ses;     // reads `features`: for the field on the host, the snap
                                           // and refinement; null where none of them needs it
    std::unique_ptr<float[]> host_values;  // the exact SES field computed on the host (plan's layout)
    bool host_ses = false;                 // the exact SES field on the host
    bool host_mc = false;                  // marching cubes on the host
};

struct EngineImpl {
    explicit EngineImpl(const EngineOptions& options)
        : glslang(), context(options), commands(context), density(context),
          ses_distance(context), filter(context), marching_cubes(context),
          vertex_properties(context), progress(options.progress),
          gaussian_filter(options.gaussian_filter), marching_cubes_place(options.marching_cubes),
          ses_distance_place(options.ses_distance), density_place(options.density),
          buffer_range_cap(options.max_buffer_range) {
        vertex_properties.set_on_host(on_host(options.vertex_atoms));
    }

    // Holds glslang for VkFFT from before the first plan to after the last.
    struct GlslangGuard {
        GlslangGuard() { glslang_acquire(); }
        ~GlslangGuard() { glslang_release(); }
    } glslang;
    Context context;
    Commands commands;
    DensityPass density;
    SesDistancePass ses_distance;
    SpectralFilter filter;
    MarchingCubesPass marching_cubes;
    VertexPropertiesPass vertex_properties;
    ProgressCallback progress;  // EngineOptions::progress; may be empty
    GaussianFilterPlace gaussian_filter;  // EngineOptions::gaussian_filter
    StagePlace marching_cubes_place;      // EngineOptions::marching_cubes
    StagePlace ses_distance_place;        // EngineOptions::ses_distance
    StagePlace density_place;             // EngineOptions::density
    // EngineOptions::max_buffer_range (0: none): caps the host's one-piece field too, so that
    // tests can force slabs there.
    std::uint64_t buffer_range_cap;

    // Makes the passes' pipelines now (each is otherwise made at its first use), but for the
    // exact SES's and the Coulombic colours': Engine::prepare's surfaces make the exact SES's
    // where the device computes that field, and a CPU device never needs them.
    void make_pipelines() const {
        density.make_pipelines();
        filter.make_pipelines();
        marching_cubes.make_pipelines();
        vertex_properties.make_pipelines();
    }

    // Whether a stage placed at `place` runs on the host: Host, or Auto on a CPU device.
    bool on_host(StagePlace place) const {
        return place == StagePlace::Host || (place == StagePlace::Auto && context.cpu_device());
    }
    // Whether the Gaussian filter of `plan` runs on the host (EngineOptions::gaussian_filter):
    // the FDM's Gaussian filter only; Auto on a CPU device.
    bool gaussian_on_host(const SurfaceOptions& options, const GridPlan& plan) const;
    // Whether the density of `plan` is computed on the host (EngineOptions::density): where
    // nothing after it runs on the device (the host's Gaussian filter, or no filter), for a
    // path whose marching cubes runs on the host.
    bool density_on_host(const SurfaceOptions& options, const GridPlan& plan) const;

    // Tells the progress callback that `stage` has ended.
    void report(std::string_view stage) const {
        if (progress) progress(stage);
    }

    // `on_device`: when not null, the mesh stays on the device there and result.mesh is empty.
    SurfaceResult run(const Atoms& atoms, const SurfaceOptions& options,
                      GpuMesh* on_device = nullptr);
    GpuMesh upload_mesh(const Mesh& mesh);
    // The attribute buffer of a mesh with per-vertex atoms and colours (Mesh::atoms, colors);
    // empty when it has no colours.
    Buffer upload_attributes(const Mesh& mesh);
    // Bytes one field buffer may take: maxStorageBufferRange, and a quarter of device memory.
    std::uint64_t field_budget() const;
    // Bytes of field that one piece may take (preflight.cpp): the device's field_budget, or for
    // the exact SES computed and marched on the host, the host's budget.
    double one_piece_limit(const SurfaceOptions& options, const GridPlan& plan,
                           bool on_device) const;
    // Whether the host alone computes and marches the field of `plan` (the exact SES's field,
    // or the density and its filter, and marching cubes on the host): no device binding holds
    // it then.
    bool field_only_on_host(const SurfaceOptions& options, const GridPlan& plan) const;
    // Bytes of field one piece (or slab) may take where the host alone computes and marches it:
    // 1 GiB, an eighth of the memory at most, and EngineOptions::max_buffer_range where set.
    double host_field_budget() const;
    // The bins or features of the one-piece field, and the exact SES field where the host
    // computes it (its stage times and progress into `result`; t0: the run's start).
    void find_field_sources(const Atoms& atoms, const SurfaceOptions& options,
                            const GridPlan& plan, bool on_device, double t0, FieldSources& src,
                            SurfaceResult& result);
    // The one-piece paths: marching cubes on the host (host_path.cpp) or on the device
    // (device_path.cpp), then the host stages.
    SurfaceResult run_on_host(const Atoms& atoms, const SurfaceOptions& options,
                              const GridPlan& plan, FieldSources& src, SurfaceResult result);
    SurfaceResult run_on_device(const Atoms& atoms, const SurfaceOptions& options,
                                const GridPlan& plan, FieldSources& src, GpuMesh* on_device,
                                SurfaceResult result);
    // A field larger than one piece, in z-slabs (slabs.cpp, slab_plan.hpp).
    SurfaceResult run_in_slabs(const Atoms& atoms, const SurfaceOptions& options, GridPlan plan,
                               SurfaceResult result);
    // The refine stage (refine_stage.cpp): options.refine levels of subdivision of result.mesh,
    // projected onto the exact SES distance of `ses` (edt), the field of `device_field` or
    // `host_field` (fdm, plan's layout) or onto the atoms' balls (vdw, sas). Nothing at 0 levels.
    void refine(SurfaceResult& result, const Atoms& atoms, const SurfaceOptions& options,
                const GridPlan& plan, const SesHostField* ses, const Buffer* device_field,
                const FieldView* host_field);
    // The host stages after marching cubes, in order: snap (edt), refine, snap (vdw, sas).
    void host_stages(SurfaceResult& result, const Atoms& atoms, const SurfaceOptions& options,
                     const GridPlan& plan, const SesHostField* ses, const Buffer* device_field,
                     const FieldView* host_field);
    // The snap stage (snap_stage.cpp): result.mesh placed on the exact surface (vdw, sas:
    // crease recovery on the balls; edt: projection onto the distance of `ses`). Nothing
    // when options.snap is off or for the FDM method.
    void snap(SurfaceResult& result, const Atoms& atoms, const SurfaceOptions& options,
              const GridPlan& plan, const SesHostField* ses);
    // Records the field of `plan` into `field`: the exact SES distance of `features` (edt), or
    // the density of `bins`, filtered for fdm.
    void record_field(StagingArena& arena, const GridPlan& plan, const AtomBins* bins,
                      const SesFeatures* features, FilterShape shape, const Buffer& field);

    // Test hooks. The density (filtered = false) or filtered density of `atoms` on `plan`'s
    // grid, read back in the plan's layout (plan.pitch floats per row).
    std::vector<float> compute_field(const Atoms& atoms, const GridPlan& plan, bool filtered,
                                     FilterShape shape = FilterShape::Ideal);
    // The exact SES field of `atoms` on `plan`'s grid (plan.exact_ses), read back;
    // force_global: the shader's per-point fallback everywhere.
    // classify false: no box skipped (SesDistancePass::record); box_classes (may be null): the
    // boxes' classes read back.
    std::vector<float> compute_ses_field(const Atoms& atoms, const GridPlan& plan,
                                         float probe, bool force_global = false,
                                         bool classify = true,
                                         std::vector<std::uint32_t>* box_classes = nullptr);
    // The spectral filter alone, on a host field in `plan`'s layout (in place).
    void filter_field(std::vector<float>& field, const GridPlan& plan, FilterShape shape);
    // GPU marching cubes on a host field; same contract as marching_cubes_cpu.
    Mesh run_marching_cubes(const FieldView& field, const McParams& params);
};

}  // namespace fdmsurf::detail
