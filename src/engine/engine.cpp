// The pipeline (Giard & Macq 2010): density, spectral filter, marching cubes, on one device.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <numbers>
#include <string>

#include "engine/engine_impl.hpp"

#include <unistd.h>
#include "base/trace.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "filter/spatial_gaussian.hpp"
#include "filter/spectral_filter.hpp"
#include "grid/atom_bins.hpp"
#include "grid/density_gpu.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "isosurface/marching_cubes_gpu.hpp"
#include "isosurface/marching_cubes_host.hpp"
#include "isosurface/slab_stitch.hpp"
#include "mesh/cavities.hpp"
#include "refine/refine.hpp"
#include "properties/vertex_properties.hpp"
#include "vulkan/check.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf {
namespace detail {

namespace {

// The largest spacing change that brings `bytes` under `limit` (sizes scale as 1/h³).
std::string spacing_hint(double bytes, double limit, float spacing) {
    double h = spacing * std::cbrt(bytes / limit) * 1.05;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.2f", std::ceil(h * 100.0) / 100.0);
    return buf;
}

}  // namespace

namespace {

// The atoms whose Gaussian support reaches global planes [z0, z1) of `plan`.
Atoms atoms_near_planes(const Atoms& atoms, const GridPlan& plan, double z0, double z1) {
    const double h = plan.info.spacing, oz = plan.info.origin[2];
    Atoms out;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        double r = atoms.radius[i] + plan.density.radius_add;
        double reach = std::sqrt(r * r + plan.density.pi_cut) + h;
        double z = atoms.xyz[3 * i + 2];
        if (z + reach < oz + z0 * h || z - reach > oz + (z1 - 1) * h) continue;
        out.xyz.insert(out.xyz.end(), atoms.xyz.begin() + 3 * i, atoms.xyz.begin() + 3 * i + 3);
        out.radius.push_back(atoms.radius[i]);
    }
    return out;
}

// Ends the recording (begun by the caller, who recorded the passes that fill `field`) with a
// read-back of `field`, submits, waits and copies the values out.
// `mark` (may be null): a stage mark recorded after the copy.
std::vector<float> read_field(EngineImpl& e, StagingArena& arena, const Buffer& field,
                              std::size_t floats, const char* mark = nullptr) {
    const std::size_t bytes = floats * sizeof(float);
    const Buffer& host =
        readback_buffer(e.context, e.commands, arena, field, bytes, "field_readback");
    if (mark) e.commands.mark(mark);
    e.commands.barrier_to_host();
    e.commands.submit_and_wait();
    host.invalidate();
    std::vector<float> out(floats);
    std::memcpy(out.data(), host.mapped(), bytes);
    return out;
}

// Planes that the filter's kernel reaches on each side of a point, enough that what lies beyond
// them is below float rounding: for the Gaussian filter 2^-(f/F)^2, whose kernel is a Gaussian
// of sigma = sqrt(ln 2 / 2) / (pi F), 6 sigma (1D tail 2e-9); for the ideal filter, whose kernel
// decays slowly, two wavelengths 2/F. None without a filter (every point is exact on its own).
std::uint32_t filter_reach_planes(const SurfaceOptions& options, const GridPlan& plan) {
    if (!plan.filtered) return 0;
    const double reach =
        options.filter == FilterShape::Gaussian
            ? 6.0 * std::sqrt(std::log(2.0) / 2.0) / (std::numbers::pi * plan.info.cutoff)
            : 2.0 / plan.info.cutoff;
    return static_cast<std::uint32_t>(std::ceil(reach / plan.info.spacing));
}

// The unfiltered density (vdw, sas) is T exp(-pi/sigma^2): its crossings are found on pi. The
// filtered density and the SES distance are interpolated linearly.
void set_interpolation(McParams& mc, const GridPlan& plan) {
    if (plan.filtered || plan.exact_ses) return;
    mc.power_sigma2 = plan.density.sigma * plan.density.sigma;
    mc.power_t = plan.density.level_t;
}

void add_times(std::vector<StageTime>& into, const std::vector<StageTime>& times) {
    for (const StageTime& t : times) {
        auto it = std::find_if(into.begin(), into.end(),
                               [&](const StageTime& u) { return u.name == t.name; });
        if (it == into.end())
            into.push_back(t);
        else
            it->ms += t.ms;
    }
}

}  // namespace

namespace {

// The host Gaussian filter's taps for `plan`: its sigma in points, over the filter's reach.
std::vector<float> host_gaussian_taps(const SurfaceOptions& options, const GridPlan& plan) {
    return gaussian_taps(gaussian_sigma_points(plan.info.cutoff, plan.info.spacing),
                         filter_reach_planes(options, plan));
}

}  // namespace

bool EngineImpl::gaussian_on_host(const SurfaceOptions& options, const GridPlan& plan) const {
    if (!plan.filtered || plan.exact_ses || options.filter != FilterShape::Gaussian) return false;
    return gaussian_filter == StagePlace::Host ||
           (on_host(gaussian_filter) &&
            gaussian_sigma_points(plan.info.cutoff, plan.info.spacing) >= kMinHostSigma);
}

namespace {

// Bytes of the machine's memory (not positive where sysconf cannot tell).
double physical_memory() {
    return double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
}

}  // namespace

// The largest field the host computes and marches in one piece (the exact SES on the host): 1 GiB
// (1AON at 0.5 Å takes 150 MB; the 4YVS assembly's 1.3 GB goes through slabs).
constexpr std::uint64_t kHostFieldBudget = std::uint64_t(1) << 30;

SurfaceResult EngineImpl::run(const Atoms& atoms, const SurfaceOptions& options,
                              GpuMesh* on_device) {
    SurfaceResult result;
    double t0 = now_ms();
    check_refine_levels(options.refine);
    trace("engine: run");
    GridPlan plan = plan_grid(atoms, options);
    result.grid = plan.info;
    trace("engine: grid planned");
    if (plan.filtered && options.spacing > 1.0f / (2.0f * plan.info.cutoff)) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "spacing %.3g Å is too coarse for the filter cut-off %.3g 1/Å: the filter "
                      "cannot act unless spacing <= 1/(2 cut-off) = %.3g Å",
                      options.spacing, plan.info.cutoff, 1.0 / (2.0 * plan.info.cutoff));
        result.warnings.emplace_back(buf);
    }
    {
        // Coordinates far from the origin: single precision's step there is a sizeable part of
        // the spacing (1CRN moved to 1e6 Å: steps of 0.06 Å, area +0.3%; at 1e7, a ball loses a
        // third of its area).
        float far = 0.0f;
        for (float c : atoms.xyz) far = std::max(far, std::fabs(c));
        const double step = double(std::nextafter(far, INFINITY)) - double(far);
        if (step > 0.05 * options.spacing) {
            char buf[300];
            std::snprintf(buf, sizeof buf,
                          "coordinates reach %.3g Å from the origin, where single precision "
                          "steps by %.2g Å (%.0f%% of the spacing): the surface loses "
                          "accuracy; move the structure nearer the origin",
                          double(far), step, 100.0 * step / options.spacing);
            result.warnings.emplace_back(buf);
        }
    }
    const double field_bytes = double(plan.field_floats()) * sizeof(float);
    // The exact SES computed and marched on the host never enters a device binding: one piece
    // while the field fits the host's budget (kHostFieldBudget, an eighth of the memory at most,
    // and EngineOptions::max_buffer_range where set), slabs beyond, which bound the host's memory
    // to a few cores of planes.
    const bool host_field_only = plan.exact_ses && !on_device && on_host(ses_distance_place) &&
                                 on_host(marching_cubes_place);
    const double host_memory = physical_memory();
    const double limit =
        host_field_only
            ? std::min({double(kHostFieldBudget), host_memory / 8.0,
                        buffer_range_cap ? double(buffer_range_cap) : double(kHostFieldBudget)})
            : double(field_budget());
    if (field_bytes > limit) {
        result = run_in_slabs(atoms, options, plan, std::move(result));
        if (on_device) *on_device = upload_mesh(result.mesh);
        return result;
    }

    const auto& d = plan.info.dims;
    AtomBins bins;
    SesFeatures features;
    // The exact SES field on the host (EngineOptions::ses_distance; not for a mesh left on the
    // device): computed here, uploaded only where marching cubes runs on the device.
    const bool host_mc = !on_device && on_host(marching_cubes_place);
    const bool host_ses = plan.exact_ses && !on_device && on_host(ses_distance_place);
    result.grid.host_ses_distance = host_ses;
    // The host's index of the features (part of the stage): for the field on the host, the snap
    // and refinement.
    std::unique_ptr<SesHostField> ses;
    if (plan.exact_ses) {
        features = build_ses_features(atoms, options.probe);
        if (host_ses || snaps(options, plan) || options.refine > 0)
            ses = std::make_unique<SesHostField>(features, plan.ses_d_max);
        result.times.push_back({"ses-features", now_ms() - t0, false});
    } else {
        bins = bin_atoms(atoms, plan);
        result.times.push_back({"bin-atoms", now_ms() - t0, false});
    }
    report(plan.exact_ses ? "ses-features" : "bin-atoms");
    trace(plan.exact_ses ? "engine: ses features" : "engine: atoms binned");
    // The host's exact SES field, in the plan's layout: written once by the evaluation (fresh
    // pages, first touched on its threads; no zero-fill before).
    std::unique_ptr<float[]> host_values;
    if (host_ses) {
        const double t_ses = now_ms();
        host_values.reset(new float[plan.field_floats()]);
        if (plan.pitch > d[0]) std::fill_n(host_values.get(), plan.field_floats(), 0.0f);
        ses->evaluate(plan, 0, d[2], host_values.get(), plan.pitch);
        add_times(result.times, {{"ses-host", now_ms() - t_ses, false}});
        report("ses-host");
    }
    StagingArena arena;
    Buffer field;
    if (!(host_ses && host_mc)) {
        field = Buffer(context, static_cast<VkDeviceSize>(field_bytes), MemoryUse::Device, "field");
        trace("engine: field allocated");
    }
    McParams mc;
    for (int a = 0; a < 3; ++a) mc.origin[a] = plan.info.origin[a];
    mc.spacing = plan.info.spacing;
    mc.iso = plan.iso;
    mc.z_begin = 0;
    mc.z_end = d[2] - 1;
    set_interpolation(mc, plan);
    // Marching cubes on the host (EngineOptions::marching_cubes; not for a mesh left on the
    // device): the field comes back, and the Gaussian filter runs on the host too where
    // gaussian_on_host says so (the host's field then holds the filtered values, which
    // refinement reads there).
    if (host_mc) {
        const bool host_gaussian = gaussian_on_host(options, plan);
        std::vector<float> values;
        const float* data = host_values.get();
        if (!host_ses) {
            commands.begin();
            if (host_gaussian)
                density.record(commands, arena, bins, plan, field);
            else
                record_field(arena, plan, &bins, &features, options.filter, field);
            values = read_field(*this, arena, field, plan.field_floats(), "read-field");
            add_times(result.times, commands.stage_times());
            data = values.data();
        }
        std::uint32_t pitch = plan.pitch;
        if (host_gaussian) {
            // Nothing reads the device's (unfiltered) field again: its memory goes before the
            // filter's.
            field = Buffer();
            arena.clear();
            const double t_filter = now_ms();
            std::vector<float> filtered(plan.points()), scratch;
            gaussian_filter_planes(values.data(), d[0], d[1], d[2], plan.pitch,
                                   host_gaussian_taps(options, plan), 0, d[2], filtered.data(),
                                   scratch);
            values = std::move(filtered);
            data = values.data();
            pitch = d[0];
            add_times(result.times, {{"filter-host", now_ms() - t_filter, false}});
        }
        const double t_mc = now_ms();
        PlaneStack planes{{}, d[0], d[1], d[2], pitch};
        for (std::uint32_t z = 0; z < d[2]; ++z)
            planes.planes.push_back(data + std::size_t(z) * d[1] * pitch);
        result.mesh = marching_cubes_host(planes, mc);
        host_values.reset();  // the exact SES's refinement and snap evaluate d itself
        add_times(result.times, {{"mc-host", now_ms() - t_mc, false}});
        result.grid.host_filter = host_gaussian;
        result.grid.host_marching_cubes = true;
        report(plan.exact_ses ? "ses-distance, marching cubes" : "density, filter, marching cubes");
        const FieldView view{values.data(), d[0], d[1], d[2], pitch};
        host_stages(result, atoms, options, plan, ses.get(),
                    host_gaussian || host_ses ? nullptr : &field,
                    host_gaussian ? &view : nullptr);
        return result;
    }
    commands.begin();
    if (host_ses) {
        write_pieces(context, commands, arena, field,
                     {{host_values.get(), plan.field_floats() * sizeof(float)}}, "field");
        commands.barrier_compute();
        commands.mark("upload-field");
    } else {
        record_field(arena, plan, &bins, &features, options.filter, field);
    }
    trace("engine: field recorded (staging, FFT plan)");
    GpuMesh gpu = marching_cubes.run(commands, arena, field, d[0], d[1], d[2], plan.pitch, mc);
    host_values.reset();  // uploaded and marched
    trace("engine: field and marching cubes done");
    add_times(result.times, marching_cubes.stage_times());
    if (on_device && options.refine == 0 && !snaps(options, plan)) {
        *on_device = std::move(gpu);
        return result;
    }
    result.mesh = marching_cubes.read_back(commands, gpu);
    trace("engine: mesh read back");
    add_times(result.times, commands.stage_times());
    add_times(result.times, {{"unpack-mesh", marching_cubes.unpack_ms(), false}});
    report(plan.exact_ses ? "ses-distance, marching cubes" : "density, filter, marching cubes");
    host_stages(result, atoms, options, plan, ses.get(), &field, nullptr);
    if (on_device) *on_device = upload_mesh(result.mesh);
    return result;
}

void EngineImpl::host_stages(SurfaceResult& result, const Atoms& atoms,
                             const SurfaceOptions& options, const GridPlan& plan,
                             const SesHostField* ses, const Buffer* device_field,
                             const FieldView* host_field) {
    // The exact SES is snapped first, so that refinement starts from vertices on the surface;
    // vdw and sas after refinement, whose butterfly stencils would smooth the creases away.
    const bool snap_now = snaps(options, plan);
    if (snap_now && plan.exact_ses) {
        snap(result, atoms, options, plan, ses);
        report("snap");
    }
    if (options.refine > 0) {
        refine(result, atoms, options, plan, ses, device_field, host_field);
        report("refine");
    }
    if (snap_now && !plan.exact_ses) {
        snap(result, atoms, options, plan, ses);
        report("snap");
    }
}

void EngineImpl::record_field(StagingArena& arena, const GridPlan& plan, const AtomBins* bins,
                              const SesFeatures* features, FilterShape shape, const Buffer& field) {
    if (plan.exact_ses) {
        ses_distance.record(commands, arena, *features, plan, field);
        return;
    }
    density.record(commands, arena, *bins, plan, field);
    if (plan.filtered) filter.record(commands, field, plan, shape);
}

std::uint64_t EngineImpl::field_budget() const {
    // One binding holds at most maxStorageBufferRange; the whole pass needs up to about four
    // times the field (field, marching cubes' words, vertices and indices, staging on a discrete
    // GPU), so a quarter of the device-local memory still free (VK_EXT_memory_budget where the
    // device has it, else the heap's size) bounds it too: larger grids go through slabs.
    const DeviceLimits& lim = context.limits();
    std::uint64_t budget = lim.max_storage_buffer_range;
    const std::uint64_t memory = context.available_device_memory();
    if (memory > 0) budget = std::min<std::uint64_t>(budget, memory / 4);
    return budget;
}

GpuMesh EngineImpl::upload_mesh(const Mesh& mesh) {
    std::vector<float> interleaved(mesh.vertex_count() * 6);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        for (int k = 0; k < 3; ++k) {
            interleaved[6 * v + k] = mesh.positions[3 * v + k];
            interleaved[6 * v + 3 + k] = mesh.normals.empty() ? 0.0f : mesh.normals[3 * v + k];
        }
    StagingArena arena;
    commands.begin();
    GpuMesh gpu;
    gpu.vertices = upload_buffer(context, commands, arena, interleaved.data(),
                                 interleaved.size() * sizeof(float), "mesh_vertices");
    gpu.indices = upload_buffer(context, commands, arena, mesh.indices.data(),
                                mesh.indices.size() * sizeof(std::uint32_t), "mesh_indices");
    gpu.vertex_count = static_cast<std::uint32_t>(mesh.vertex_count());
    gpu.triangle_count = static_cast<std::uint32_t>(mesh.triangle_count());
    // On a discrete GPU the uploads are copies (transfer writes): made available here, so that
    // the barrier a renderer records for a DeviceMesh (compute-shader writes to vertex input,
    // fdmsurf/vulkan_interop.hpp) chains on and covers them as well.
    commands.barrier_compute();
    commands.mark("upload-mesh");
    commands.submit_and_wait();
    return gpu;
}

Buffer EngineImpl::upload_attributes(const Mesh& mesh) {
    const std::size_t nv = mesh.vertex_count();
    if (mesh.colors.size() != 3 * nv || nv == 0) return {};
    std::vector<std::uint32_t> words(2 * nv);
    for (std::size_t v = 0; v < nv; ++v) {
        words[2 * v] = mesh.atoms.size() == nv ? mesh.atoms[v] : 0xffffffffu;
        words[2 * v + 1] =
            pack_rgba({mesh.colors[3 * v], mesh.colors[3 * v + 1], mesh.colors[3 * v + 2]});
    }
    StagingArena arena;
    commands.begin();
    Buffer out = upload_buffer(context, commands, arena, words.data(),
                               words.size() * sizeof(std::uint32_t), "mesh_attributes");
    commands.barrier_compute();  // as in upload_mesh
    commands.submit_and_wait();
    return out;
}

// A grid larger than one storage-buffer binding: the density and the filter run on overlapping
// z-slabs (the overlap absorbs the truncation and the circular wrap of each slab's FFT), their
// cores come back to the host one after the other, and marching cubes runs on each core (with
// a plane of its neighbours on both sides), the parts stitched by shared-plane vertex identity.
SurfaceResult EngineImpl::run_in_slabs(const Atoms& atoms, const SurfaceOptions& options,
                                       GridPlan plan, SurfaceResult result) {
    const auto d = plan.info.dims;
    const double h = plan.info.spacing;
    const std::uint64_t limit = field_budget();
    const std::uint64_t plane_bytes = std::uint64_t(plan.pitch) * d[1] * sizeof(float);
    // Overlap on each side, enough that the filter kernel's reach from outside the slab (and
    // the circular wrap of the slab's FFT) is below float rounding in the core.
    const std::uint32_t overlap = filter_reach_planes(options, plan);
    // The fewest slabs whose planes fit one binding, each as thin as they allow (FFT sizes of
    // 2, 3, 5 and 7 only): every plane beyond the grid's is FFT work for nothing.
    const std::uint64_t fit =
        std::min<std::uint64_t>(limit / plane_bytes, std::uint64_t(d[2]) + 2 * overlap);
    auto planes_for = [&](std::uint32_t count) {
        std::uint32_t n = (d[2] + count - 1) / count + 2 * overlap;
        return plan.filtered ? fft_friendly_size(n, false) : n;
    };
    // Marching cubes then reads a core with a plane under it and two above (pitch nx): that
    // must fit one binding too (it decides for the exact SES, whose slabs have no overlap).
    const std::uint64_t mc_plane_bytes = std::uint64_t(d[0]) * d[1] * sizeof(float);
    std::uint32_t slab_planes = 0;
    for (std::uint32_t count = 2; (d[2] + count - 1) / count >= 8; ++count) {
        const std::uint32_t n = planes_for(count);
        const std::uint64_t mc_planes = n - 2 * overlap + 3;  // the core, as rounded for the FFT
        if (n <= fit && mc_planes * mc_plane_bytes <= limit) {
            slab_planes = n;
            break;
        }
    }
    if (slab_planes == 0) {
        const double need = std::max(double(plane_bytes) * (2 * overlap + 8),
                                     double(mc_plane_bytes) * (8 + 3));
        throw Error(ErrorCode::DeviceLimit,
                    "the grid of " + std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " +
                        std::to_string(d[2]) + " points is too wide to be processed in z-slabs " +
                        "within this device's maxStorageBufferRange (" +
                        std::to_string(limit >> 20) + " MiB); a spacing of " +
                        spacing_hint(need, double(limit), options.spacing) + " Å would fit" +
                        isolated_atoms_note(atoms));
    }
    const std::uint32_t core = slab_planes - 2 * overlap;
    // The host holds up to three cores at a time (the pending one, the one just read, the part
    // being uploaded), or the whole field where refinement reads it (the filtered SES): that
    // must fit the machine's memory, with room for the mesh.
    const bool gather_field = options.refine > 0 && plan.filtered && !plan.exact_ses;
    const double host_field = gather_field
                                  ? double(d[0]) * d[1] * d[2] * sizeof(float)
                                  : 3.0 * double(core + 3) * double(mc_plane_bytes);
    const double host_memory = physical_memory();
    if (host_memory > 0 && host_field > 0.5 * host_memory) {
        char figures[160];
        std::snprintf(figures, sizeof figures, "%.1f GiB of host memory, more than half of this machine's %.1f GiB",
                      host_field / (1 << 30), host_memory / (1 << 30));
        throw Error(ErrorCode::DeviceLimit,
                    "the grid of " + std::to_string(d[0]) + " x " + std::to_string(d[1]) + " x " +
                        std::to_string(d[2]) + " points is processed in slabs whose field needs " +
                        figures + "; a spacing of " +
                        spacing_hint(host_field, 0.5 * host_memory, options.spacing) +
                        " Å would fit" + isolated_atoms_note(atoms));
    }
    const std::uint32_t slabs = (d[2] + core - 1) / core;
    result.grid.slabs = slabs;

    // Density and filter, slab by slab. Each slab's core planes come back to the host, and
    // marching cubes runs on the cells of slab k's core once slab k + 1's first planes are in:
    // its top cells and the gradients there (one extra plane on both sides, so that the normals
    // equal those of a single pass) need them. The host keeps only the core whose cells are
    // pending (and the one just read), the plane under it, and the two planes of each seam for
    // the stitch; the whole field is gathered only for refinement of the filtered SES, which
    // reads it anywhere (1.3 GB for the 686³ grid of the 4YVS assembly). The slab buffer stays
    // while marching cubes runs on the earlier cores (one more buffer of at most field_budget()
    // beside marching cubes' own; released before the last).
    const std::size_t plane_floats = std::size_t(d[0]) * d[1];
    std::vector<float> full(gather_field ? plane_floats * d[2] : 0);
    GridPlan sp = plan;
    sp.info.dims[2] = slab_planes;
    const std::size_t slab_bytes = sp.field_floats() * sizeof(float);
    // The exact SES is evaluated per point from the features of all atoms (binned once); the
    // density of each slab from the atoms that reach it.
    SesFeatures features;
    // The host's index of the features: for the field on the host (EngineOptions::ses_distance),
    // the snap and refinement.
    std::unique_ptr<SesHostField> ses;
    const bool host_ses = plan.exact_ses && on_host(ses_distance_place);
    if (plan.exact_ses) {
        const double t0 = now_ms();
        features = build_ses_features(atoms, options.probe);
        add_times(result.times, {{"ses-features", now_ms() - t0, false}});
        if (host_ses || snaps(options, plan) || options.refine > 0)
            ses = std::make_unique<SesHostField>(features, plan.ses_d_max);
    }
    result.grid.host_ses_distance = host_ses;
    std::vector<Mesh> parts;
    std::vector<std::uint32_t> starts;
    const bool host_mc = on_host(marching_cubes_place);
    result.grid.host_marching_cubes = host_mc;
    std::map<std::uint32_t, std::vector<float>> seams;  // plane z -> its values, for the stitch
    std::vector<float> pending, below;  // the core of the slab whose cells are next; the plane under it
    std::uint32_t pending_z0 = 0;
    // Marching cubes on the cells of the pending core [a, b], from the plane under it, the core
    // and the first planes of the next one (`next`, starting at plane b when b < d[2] - 1).
    Buffer part_field;
    auto mc_part = [&](const std::vector<float>& next) {
        const std::uint32_t core_planes = static_cast<std::uint32_t>(pending.size() / plane_floats);
        const std::uint32_t a = pending_z0;
        const std::uint32_t b = std::min(a + core_planes, d[2] - 1);
        if (a + 1 >= d[2]) return;  // a last core of one plane: its cells belong to the part below
        const std::uint32_t lo = a > 0 ? a - 1 : 0;
        const std::uint32_t hi = std::min(b + 1, d[2] - 1);
        const std::uint32_t from_next = hi >= a + core_planes ? hi - (a + core_planes) + 1 : 0;
        McParams mc;
        mc.origin[0] = plan.info.origin[0];
        mc.origin[1] = plan.info.origin[1];
        mc.origin[2] = static_cast<float>(plan.info.origin[2] + lo * h);
        mc.spacing = plan.info.spacing;
        mc.iso = plan.iso;
        mc.z_begin = a - lo;
        mc.z_end = b - lo;
        set_interpolation(mc, plan);
        if (host_mc) {
            // The planes where they are: the one under the core, the core, the next core's first.
            const double t_mc = now_ms();
            PlaneStack planes{{}, d[0], d[1], hi - lo + 1, d[0]};
            if (a > lo) planes.planes.push_back(below.data());
            for (std::uint32_t z = 0; z < core_planes; ++z)
                planes.planes.push_back(pending.data() + std::size_t(z) * plane_floats);
            for (std::uint32_t z = 0; z < from_next; ++z)
                planes.planes.push_back(next.data() + std::size_t(z) * plane_floats);
            parts.push_back(marching_cubes_host(planes, mc));
            add_times(result.times, {{"mc-host", now_ms() - t_mc, false}});
            report("marching cubes, z " + std::to_string(b) + "/" + std::to_string(d[2] - 1));
            starts.push_back(a);
            return;
        }
        StagingArena arena;
        const double t_upload = now_ms();
        commands.begin();
        // One buffer for every part (the largest: a full core and its three planes), written
        // again for each: fresh pages for each part cost more than the copy.
        if (part_field.size() == 0)
            part_field = Buffer(context, (std::size_t(core) + 3) * mc_plane_bytes,
                                MemoryUse::Device, "field_part");
        write_pieces(
            context, commands, arena, part_field,
            {{below.data(), a > lo ? mc_plane_bytes : 0},
             {pending.data(), pending.size() * sizeof(float)},
             {next.data(), from_next * mc_plane_bytes}},
            "field_part");
        add_times(result.times, {{"upload-part", now_ms() - t_upload, false}});
        commands.barrier_compute();
        GpuMesh gpu =
            marching_cubes.run(commands, arena, part_field, d[0], d[1], hi - lo + 1, d[0], mc);
        add_times(result.times, marching_cubes.stage_times());
        parts.push_back(marching_cubes.read_back(commands, gpu));
        add_times(result.times, commands.stage_times());
        add_times(result.times, {{"unpack-mesh", marching_cubes.unpack_ms(), false}});
        report("marching cubes, z " + std::to_string(b) + "/" + std::to_string(d[2] - 1));
        starts.push_back(a);
    };
    // The Gaussian filter on the host (gaussian_on_host): the slab's density comes back and its
    // core is convolved there, with a kernel as wide as the overlap (6 sigma).
    const bool host_gaussian = gaussian_on_host(options, plan);
    std::vector<float> taps, filter_scratch;
    if (host_gaussian) taps = host_gaussian_taps(options, plan);
    result.grid.host_filter = host_gaussian;
    Buffer field;
    if (!host_ses) field = Buffer(context, slab_bytes, MemoryUse::Device, "field_slab");
    std::vector<float> slab_core;  // two core buffers, swapped: pages touched once, not per slab
    for (std::uint32_t k = 0; k < slabs; ++k) {
        const std::int64_t zc0 = std::int64_t(k) * core;
        const std::int64_t zc1 = std::min<std::int64_t>(zc0 + core, d[2]);
        const std::int64_t z0 = zc0 - overlap;
        sp.info.origin[2] = static_cast<float>(plan.info.origin[2] + z0 * h);
        slab_core.resize(std::size_t(zc1 - zc0) * plane_floats);
        double t0 = now_ms();
        StagingArena arena;
        AtomBins bins;
        bool empty = false;
        if (!plan.exact_ses) {
            Atoms near = atoms_near_planes(atoms, plan, double(z0), double(z0 + slab_planes));
            empty = near.empty();
            if (!empty) {
                bins = bin_atoms(near, sp);
                add_times(result.times, {{"bin-atoms", now_ms() - t0, false}});
            }
        }
        if (empty) {
            // Nothing reaches an empty slab: its density, and so its filtered field, is 0.
            std::fill(slab_core.begin(), slab_core.end(), 0.0f);
        } else if (host_ses) {
            // The exact SES has no overlap: the core's planes straight into the core.
            ses->evaluate(plan, std::uint32_t(zc0), std::uint32_t(zc1), slab_core.data(),
                               d[0]);
            add_times(result.times, {{"ses-host", now_ms() - t0, false}});
            report("field slab " + std::to_string(k + 1) + "/" + std::to_string(slabs));
        } else {
            commands.begin();
            if (host_gaussian)
                density.record(commands, arena, bins, sp, field);  // filtered below, on the host
            else
                record_field(arena, sp, &bins, &features, options.filter, field);
            const Buffer& host =
                readback_buffer(context, commands, arena, field, slab_bytes, "field_readback");
            commands.barrier_to_host();
            commands.mark("read-field");
            commands.submit_and_wait();
            add_times(result.times, commands.stage_times());
            report("field slab " + std::to_string(k + 1) + "/" + std::to_string(slabs));
            host.invalidate();
            const double t_copy = now_ms();
            const float* src = static_cast<const float*>(host.mapped());
            if (host_gaussian) {
                gaussian_filter_planes(src, d[0], d[1], slab_planes, sp.pitch, taps,
                                       std::uint32_t(zc0 - z0), std::uint32_t(zc1 - z0),
                                       slab_core.data(), filter_scratch);
                add_times(result.times, {{"filter-host", now_ms() - t_copy, false}});
            } else {
                for (std::int64_t z = zc0; z < zc1; ++z)
                    for (std::uint32_t y = 0; y < d[1]; ++y)
                        std::memcpy(&slab_core[(std::size_t(z - zc0) * d[1] + y) * d[0]],
                                    src + (std::size_t(z - z0) * d[1] + y) * sp.pitch,
                                    d[0] * sizeof(float));
                add_times(result.times, {{"assemble-field", now_ms() - t_copy, false}});
            }
        }
        if (!full.empty())
            std::copy(slab_core.begin(), slab_core.end(), full.begin() + zc0 * plane_floats);
        // The slab buffer is released before marching cubes on the last cores allocates its
        // buffers (the earlier parts run beside it).
        if (k + 1 == slabs) field = Buffer();
        if (k > 0) {
            // The seam at zc0: the stitch reads planes zc0 and zc0 + 1 (both in this core, which
            // has at least 8 planes unless it is the last, where zc0 + 1 may not exist).
            for (std::int64_t z = zc0; z < std::min<std::int64_t>(zc0 + 2, zc1); ++z)
                seams[std::uint32_t(z)].assign(slab_core.begin() + (z - zc0) * plane_floats,
                                               slab_core.begin() + (z - zc0 + 1) * plane_floats);
            mc_part(slab_core);
            below.assign(pending.end() - plane_floats, pending.end());
        }
        std::swap(pending, slab_core);
        pending_z0 = std::uint32_t(zc0);
    }
    mc_part({});
    part_field = Buffer();
    pending = {};
    slab_core = {};
    below = {};
    starts.push_back(d[2] - 1);
    double t1 = now_ms();
    const SlabPlanes seam_planes{d[0], d[1], d[2], [&](std::uint32_t z) -> const float* {
                                     const auto it = seams.find(z);
                                     if (it == seams.end())
                                         throw Error(ErrorCode::Internal,
                                                     "stitch: plane " + std::to_string(z) +
                                                         " was not kept");
                                     return it->second.data();
                                 }};
    result.mesh = stitch_slabs(parts, seam_planes, plan.iso, starts);
    result.times.push_back({"stitch", now_ms() - t1, false});
    report("stitch");
    seams.clear();
    const FieldView view{full.data(), d[0], d[1], d[2], d[0]};
    host_stages(result, atoms, options, plan, ses.get(), nullptr, full.empty() ? nullptr : &view);
    return result;
}


std::vector<float> EngineImpl::compute_ses_field(const Atoms& atoms, const GridPlan& plan,
                                                 float probe, bool force_global, bool classify,
                                                 std::vector<std::uint32_t>* box_classes) {
    const SesFeatures features = build_ses_features(atoms, probe);
    StagingArena arena;
    Buffer field(context, plan.field_floats() * sizeof(float), MemoryUse::Device, "field");
    commands.begin();
    ses_distance.record(commands, arena, features, plan, field, force_global, classify);
    const Buffer* classes = nullptr;
    std::size_t boxes = 0;
    if (box_classes) {
        const auto b = ses_boxes(plan);
        boxes = std::size_t(b[0]) * b[1] * b[2];
        classes = &readback_buffer(context, commands, arena, ses_distance.box_classes(),
                                   boxes * sizeof(std::uint32_t), "box_classes_readback");
    }
    std::vector<float> out = read_field(*this, arena, field, plan.field_floats());
    if (box_classes) {
        classes->invalidate();
        const auto* words = static_cast<const std::uint32_t*>(classes->mapped());
        box_classes->assign(words, words + boxes);
    }
    return out;
}

std::vector<float> EngineImpl::compute_field(const Atoms& atoms, const GridPlan& plan,
                                             bool filtered, FilterShape shape) {
    AtomBins bins = bin_atoms(atoms, plan);
    StagingArena arena;
    Buffer field(context, plan.field_floats() * sizeof(float), MemoryUse::Device, "field");
    commands.begin();
    density.record(commands, arena, bins, plan, field);
    if (filtered) filter.record(commands, field, plan, shape);
    return read_field(*this, arena, field, plan.field_floats());
}

void EngineImpl::filter_field(std::vector<float>& values, const GridPlan& plan, FilterShape shape) {
    StagingArena arena;
    const std::size_t bytes = values.size() * sizeof(float);
    commands.begin();
    Buffer field = upload_buffer(context, commands, arena, values.data(), bytes, "field");
    commands.barrier_compute();
    filter.record(commands, field, plan, shape);
    values = read_field(*this, arena, field, values.size());
}

Mesh EngineImpl::run_marching_cubes(const FieldView& f, const McParams& params) {
    StagingArena arena;
    const std::size_t bytes = std::size_t(f.pitch) * f.ny * f.nz * sizeof(float);
    commands.begin();
    Buffer field = upload_buffer(context, commands, arena, f.data, bytes, "field");
    commands.barrier_compute();
    GpuMesh gpu = marching_cubes.run(commands, arena, field, f.nx, f.ny, f.nz, f.pitch, params);
    return marching_cubes.read_back(commands, gpu);
}

}  // namespace detail

Engine::Engine(const EngineOptions& options)
    : impl_(std::make_unique<detail::EngineImpl>(options)) {}
Engine::~Engine() = default;
Engine::Engine(Engine&&) noexcept = default;
Engine& Engine::operator=(Engine&&) noexcept = default;

std::vector<Engine::PreparedPlan> Engine::prepare() {
    // lavapipe compiles a kernel to machine code at its first dispatch, not when its pipeline
    // is made: each plan is therefore run, in the surface of one atom on a grid of that size
    // (min_grid), which also runs every stage of the default surface once. The exact SES, vdw
    // and sas surfaces of the atom then run their own kernels (their grids need no FFT).
    impl_->make_pipelines();  // into the driver's pipeline cache
    Atoms atom;
    atom.xyz = {0.0f, 0.0f, 0.0f};
    atom.radius = {1.7f};
    atom.element = {"C"};
    std::vector<PreparedPlan> rows;
    for (std::uint32_t c : detail::kCanonicalGridSizes) {
        PreparedPlan row;
        row.dims = {c, c, c};
        const double t0 = detail::now_ms();
        const auto status = impl_->filter.prepare(row.dims);
        row.from_cache = status.from_cache;
        row.stored = status.stored;
        SurfaceOptions fdm;
        fdm.min_grid = row.dims;
        make_surface(atom, fdm);
        row.ms = detail::now_ms() - t0;
        rows.push_back(row);
        impl_->report("prepare " + std::to_string(c));
    }
    SurfaceOptions edt;
    edt.method = SesMethod::Edt;
    make_surface(atom, edt);
    for (SurfaceKind kind : {SurfaceKind::Vdw, SurfaceKind::Sas}) {
        SurfaceOptions balls;
        balls.surface = kind;
        make_surface(atom, balls);
    }
    impl_->report("prepare exact surfaces");
    return rows;
}

namespace {

// The warning for a surface without triangles: no grid point inside it, which a finer spacing
// (or, with --level, a lower level) would change.
std::string empty_surface_warning(const Atoms& atoms, const SurfaceOptions& options) {
    const float add = options.surface == SurfaceKind::Sas ? options.probe : 0.0f;
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r + add);
    char buf[300];
    std::snprintf(buf, sizeof buf,
                  "the surface is empty: no grid point lies inside it (spacing %.3g Å, atoms of "
                  "radius %.3g Å at most%s); a finer spacing%s would find it",
                  double(options.spacing), double(r_max), add > 0.0f ? " with the probe" : "",
                  options.level > 0.0f ? " or a lower level" : "");
    return buf;
}

}  // namespace

SurfaceResult Engine::make_surface(const Atoms& atoms, const SurfaceOptions& options) {
    std::vector<std::string> property_warnings =
        detail::check_property_inputs(atoms, options.properties);
    SurfaceResult result = impl_->run(atoms, options);
    result.warnings.insert(result.warnings.end(), property_warnings.begin(),
                           property_warnings.end());
    const double t0 = detail::now_ms();
    const bool ses = options.surface == SurfaceKind::Ses;
    const bool fdm = ses && options.method == SesMethod::Fdm;
    if (ses && !fdm) {
        // The exact SES touches itself at isolated points (where probes meet around a tiny
        // unswept gap); the grid turns some into closed specks far smaller than a cell.
        const double h = options.spacing;
        result.specks_removed = detail::remove_specks(result.mesh, h * h * h);
    }
    if (options.min_cavity_volume >= 0.0f) {
        if (options.min_cavity_volume > 0.0f)
            result.cavities_removed = remove_cavities(result.mesh, options.min_cavity_volume);
    } else if (fdm) {
        // A void is part of the SES only if the probe fits in it; the filter also opens voids
        // where it does not (and closes some where it does).
        result.cavities_removed =
            detail::remove_cavities_without_probe(result.mesh, atoms, options.probe);
    }
    // (By default the exact SES, vdw and sas keep every cavity.)
    if (result.mesh.triangle_count() == 0 && !atoms.empty())
        result.warnings.push_back(empty_surface_warning(atoms, options));
    result.times.push_back({"cavities", detail::now_ms() - t0, false});
    impl_->report("cavities");
    detail::trace("engine: cavities");
    // On the final mesh: the atom of each vertex, colours and scalars.
    detail::add_vertex_properties(impl_->vertex_properties, impl_->commands, atoms, options,
                                  result);
    impl_->report("vertex properties");
    detail::trace("engine: vertex properties");
    return result;
}

DeviceSurfaceResult Engine::make_device_surface(const Atoms& atoms, const SurfaceOptions& options) {
    const PropertyOptions& po = options.properties;
    if (!po.scalars.empty())
        throw Error(ErrorCode::InvalidArgument,
                    "make_device_surface: per-vertex properties are computed on the host mesh "
                    "only (make_surface); ask for none here");
    if (po.color == ColorScheme::Coulombic)
        throw Error(ErrorCode::InvalidArgument,
                    "make_device_surface: the coulombic colours are computed on the host mesh "
                    "only (make_surface, then Engine::upload_mesh)");
    std::vector<std::string> property_warnings = detail::check_property_inputs(atoms, po);
    detail::GpuMesh gpu;
    SurfaceResult host = impl_->run(atoms, options, &gpu);
    DeviceSurfaceResult out;
    out.mesh.buffers_ = std::make_unique<detail::DeviceMeshBuffers>();
    if (po.color != ColorScheme::None) {
        out.mesh.buffers_->attributes =
            detail::device_mesh_attributes(impl_->vertex_properties, impl_->commands, atoms,
                                           options, gpu, host.grid, host.times);
        impl_->report("vertex colours");
    }
    out.mesh.buffers_->mesh = std::move(gpu);
    out.grid = host.grid;
    out.times = std::move(host.times);
    out.warnings = std::move(host.warnings);
    out.warnings.insert(out.warnings.end(), property_warnings.begin(), property_warnings.end());
    if (out.mesh.triangle_count() == 0 && !atoms.empty())
        out.warnings.push_back(empty_surface_warning(atoms, options));
    return out;
}

DeviceMesh Engine::upload_mesh(const Mesh& mesh) {
    if (mesh.positions.size() % 3 != 0 || mesh.indices.size() % 3 != 0 ||
        (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size()) ||
        (!mesh.colors.empty() && mesh.colors.size() != mesh.positions.size()))
        throw Error(ErrorCode::InvalidArgument,
                    "upload_mesh: positions, normals, colours and indices disagree in size");
    const std::size_t nv = mesh.vertex_count();
    for (std::uint32_t i : mesh.indices)
        if (i >= nv)
            throw Error(ErrorCode::InvalidArgument,
                        "upload_mesh: an index refers to vertex " + std::to_string(i) + " of " +
                            std::to_string(nv));
    DeviceMesh out;
    out.buffers_ = std::make_unique<detail::DeviceMeshBuffers>();
    if (mesh.normals.empty() && nv > 0) {
        // A renderer lights by the normals: without them, each vertex gets the area-weighted
        // mean of its triangles' normals.
        Mesh with_normals = mesh;
        with_normals.normals.assign(3 * nv, 0.0f);
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
            const std::uint32_t* f = &mesh.indices[3 * t];
            const float* a = &mesh.positions[3 * f[0]];
            const float* b = &mesh.positions[3 * f[1]];
            const float* c = &mesh.positions[3 * f[2]];
            const float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const float w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const float n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                u[0] * w[1] - u[1] * w[0]};
            for (int k = 0; k < 3; ++k)
                for (int j = 0; j < 3; ++j) with_normals.normals[3 * f[k] + j] += n[j];
        }
        for (std::size_t v = 0; v < nv; ++v) {
            float* n = &with_normals.normals[3 * v];
            const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (len > 0.0f)
                for (int j = 0; j < 3; ++j) n[j] /= len;
        }
        out.buffers_->mesh = impl_->upload_mesh(with_normals);
    } else {
        out.buffers_->mesh = impl_->upload_mesh(mesh);
    }
    out.buffers_->attributes = impl_->upload_attributes(mesh);
    return out;
}

DeviceMesh::DeviceMesh() = default;
DeviceMesh::~DeviceMesh() = default;
DeviceMesh::DeviceMesh(DeviceMesh&&) noexcept = default;
DeviceMesh& DeviceMesh::operator=(DeviceMesh&&) noexcept = default;
VkBuffer DeviceMesh::vertex_buffer() const {
    return buffers_ ? buffers_->mesh.vertices.handle() : VK_NULL_HANDLE;
}
VkBuffer DeviceMesh::index_buffer() const {
    return buffers_ ? buffers_->mesh.indices.handle() : VK_NULL_HANDLE;
}
VkBuffer DeviceMesh::attribute_buffer() const {
    return buffers_ ? buffers_->attributes.handle() : VK_NULL_HANDLE;
}
std::uint32_t DeviceMesh::vertex_count() const {
    return buffers_ ? buffers_->mesh.vertex_count : 0;
}
std::uint32_t DeviceMesh::triangle_count() const {
    return buffers_ ? buffers_->mesh.triangle_count : 0;
}

const DeviceInfo& Engine::device() const { return impl_->context.info(); }

std::vector<std::string> Engine::take_validation_messages() {
    return impl_->context.take_messages();
}

std::vector<DeviceInfo> list_devices() {
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.apiVersion = VK_API_VERSION_1_1;
    VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    info.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vkCreateInstance(&info, nullptr, &instance);
    if (r != VK_SUCCESS) throw Error(ErrorCode::NoDevice, detail::no_device_help(), r);
    std::vector<DeviceInfo> out;
    std::uint32_t count = 0;
    vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    if (count) vkEnumeratePhysicalDevices(instance, &count, devices.data());
    for (std::uint32_t i = 0; i < count; ++i) out.push_back(detail::describe_device(devices[i], i));
    vkDestroyInstance(instance, nullptr);
    return out;
}

}  // namespace fdmsurf
