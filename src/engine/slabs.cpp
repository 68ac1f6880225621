// A grid larger than one storage-buffer binding: the density and the filter run on overlapping
// z-slabs (the overlap absorbs the truncation and the circular wrap of each slab's FFT), their
// cores come back to the host one after the other, and marching cubes runs on each core (with
// a plane of its neighbours on both sides), the parts stitched by shared-plane vertex identity.
// The slab sizes come from plan_slabs (slab_plan.hpp).
#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "base/fresh_pages.hpp"
#include "engine/engine_impl.hpp"
#include "fdmsurf/error.hpp"
#include "engine/engine_steps.hpp"
#include "engine/slab_plan.hpp"
#include "filter/spatial_gaussian.hpp"
#include "grid/density_host.hpp"
#include "isosurface/marching_cubes_host.hpp"
#include "isosurface/slab_stitch.hpp"

namespace fdmsurf::detail {

namespace {

// Marching cubes on the cores of the slabs as they come in: the cells of the pending core
// [a, b] are marched from the plane under it, the core and the first planes of the next one,
// on the host or on the device, each part appended to the one mesh and stitched to the next
// there (its top plane's vertices dropped for the next part's copies), so that no part is
// copied again.
struct SlabMarcher {
    EngineImpl& e;
    const GridPlan& plan;
    SurfaceResult& result;
    std::uint32_t core = 0;  // planes of a full core
    bool host_mc = false;
    std::size_t plane_floats = 0;
    std::uint64_t mc_plane_bytes = 0;
    Mesh mesh;  // the parts so far, stitched
    double stitch_ms = 0.0;
    double surface_z0 = 0.0, surface_z1 = 0.0;  // the planes of the atoms' extent, probe added
    std::vector<float> pending,
        below;  // the core of the slab whose cells are next; the plane under it
    std::uint32_t pending_z0 = 0;
    // One buffer for every part on the device (the largest: a full core and its three planes),
    // written again for each: fresh pages for each part cost more than the copy.
    Buffer part_field;

    // Marching cubes on the pending core, with `next` the next core's planes (starting at plane
    // b when b < d[2] - 1; empty after the last).
    void march(const std::vector<float>& next) {
        const auto& d = plan.info.dims;
        const double h = plan.info.spacing;
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
        // Room for the parts to come when the mesh must grow (address space only; see
        // grow_mesh_for_part): a surface has about as many triangles on each plane of the
        // molecule's height (a sphere's zones of equal height have equal areas), so the planes
        // of the atoms' extent still to march as many per plane as those so far, three times
        // over: 1AON's middle planes hold twice its mean (a margin of 1.5 made it grow and copy
        // 58% of its mesh at 0.25 Å, 3 copies 8%: the first parts, small, at the extent's end).
        const double span = std::max(surface_z1 - surface_z0, 1.0);
        const double done = std::clamp(double(b) - surface_z0, span / 16, span);
        const double reserve_scale = b + 1 < d[2] ? 3.0 * span / done : 1.0;
        const std::size_t first_vertex = mesh.vertex_count(), first_index = mesh.indices.size();
        if (host_mc)
            march_on_host(next, mc, a, lo, hi, core_planes, from_next, reserve_scale);
        else
            march_on_device(next, mc, a, lo, hi, from_next, reserve_scale);
        e.report("marching cubes, z " + std::to_string(b) + "/" + std::to_string(d[2] - 1));
        if (b + 1 < d[2]) {
            // Plane b is the next part's bottom plane: its first two planes are b and b + 1.
            const double t = now_ms();
            stitch_top_plane(mesh, first_vertex, first_index, next.data(),
                             next.data() + plane_floats, d[0], d[1], plan.iso);
            stitch_ms += now_ms() - t;
        }
    }

    // The planes where they are: the one under the core, the core, the next core's first.
    void march_on_host(const std::vector<float>& next, const McParams& mc, std::uint32_t a,
                       std::uint32_t lo, std::uint32_t hi, std::uint32_t core_planes,
                       std::uint32_t from_next, double reserve_scale) {
        const auto& d = plan.info.dims;
        const double t_mc = now_ms();
        PlaneStack planes{{}, d[0], d[1], hi - lo + 1, d[0]};
        if (a > lo) planes.planes.push_back(below.data());
        for (std::uint32_t z = 0; z < core_planes; ++z)
            planes.planes.push_back(pending.data() + std::size_t(z) * plane_floats);
        for (std::uint32_t z = 0; z < from_next; ++z)
            planes.planes.push_back(next.data() + std::size_t(z) * plane_floats);
        marching_cubes_host_append(planes, mc, mesh, reserve_scale);
        add_times(result.times, {{"mc-host", now_ms() - t_mc, false}});
    }

    // The same planes uploaded into part_field and marched on the device.
    void march_on_device(const std::vector<float>& next, const McParams& mc, std::uint32_t a,
                         std::uint32_t lo, std::uint32_t hi, std::uint32_t from_next,
                         double reserve_scale) {
        const auto& d = plan.info.dims;
        StagingArena arena;
        const double t_upload = now_ms();
        e.commands.begin();
        if (part_field.size() == 0)
            part_field = Buffer(e.context, (std::size_t(core) + 3) * mc_plane_bytes,
                                MemoryUse::Device, "field_part");
        write_pieces(e.context, e.commands, arena, part_field,
                     {{below.data(), a > lo ? mc_plane_bytes : 0},
                      {pending.data(), pending.size() * sizeof(float)},
                      {next.data(), from_next * mc_plane_bytes}},
                     "field_part");
        add_times(result.times, {{"upload-part", now_ms() - t_upload, false}});
        e.commands.barrier_compute();
        GpuMesh gpu =
            e.marching_cubes.run(e.commands, arena, part_field, d[0], d[1], hi - lo + 1, d[0], mc);
        add_times(result.times, e.marching_cubes.stage_times());
        e.marching_cubes.read_back_append(e.commands, gpu, mesh, reserve_scale);
        add_times(result.times, e.commands.stage_times());
        add_times(result.times, {{"unpack-mesh", e.marching_cubes.unpack_ms(), false}});
    }
};

// The slabs' fields, one after the other: the density of the atoms that reach the slab (then
// filtered, on the device or on the host) read back into the slab's core, or the exact SES
// evaluated on the host straight into the core.
struct SlabFields {
    EngineImpl& e;
    const Atoms& atoms;
    const SurfaceOptions& options;
    const GridPlan& plan;
    const SesFeatures& features;
    const SesHostField* ses;  // the exact SES's host index (may be null)
    SurfaceResult& result;
    SlabPlan slab;
    bool host_ses = false;
    bool host_gaussian = false;
    bool host_density = false;
    GridPlan sp;   // one slab's plan: its dims[2] the slab's planes, its origin moved per slab
    Buffer field;  // the device's slab field (none where the host computes the field)
    std::vector<float> taps, filter_scratch;  // the host Gaussian filter's
    std::vector<float> density;  // the host's density of a whole slab (nx floats a row)

    // Slab k's core planes into `slab_core`.
    void compute(std::uint32_t k, std::vector<float>& slab_core) {
        const auto d = plan.info.dims;
        const double h = plan.info.spacing;
        const std::int64_t zc0 = std::int64_t(k) * slab.core;
        const std::int64_t zc1 = std::min<std::int64_t>(zc0 + slab.core, d[2]);
        const std::int64_t z0 = zc0 - slab.overlap;
        sp.info.origin[2] = static_cast<float>(plan.info.origin[2] + z0 * h);
        const double t0 = now_ms();
        StagingArena arena;
        AtomBins bins;
        bool empty = false;
        if (!plan.exact_ses) {
            Atoms near = atoms_near_planes(atoms, plan, double(z0), double(z0 + slab.slab_planes));
            empty = near.empty();
            if (!empty) {
                bins = bin_atoms(near, sp, !host_density);
                add_times(result.times, {{"bin-atoms", now_ms() - t0, false}});
            }
        }
        if (empty) {
            // Nothing reaches an empty slab: its density, and so its filtered field, is 0.
            std::fill(slab_core.begin(), slab_core.end(), 0.0f);
            return;
        }
        if (host_ses) {
            // The exact SES has no overlap: the core's planes straight into the core.
            ses->evaluate(plan, std::uint32_t(zc0), std::uint32_t(zc1), slab_core.data(), d[0]);
            add_times(result.times, {{"ses-host", now_ms() - t0, false}});
            e.report("field slab " + std::to_string(k + 1) + "/" + std::to_string(slab.slabs));
            return;
        }
        if (host_density) {
            density_on_host(bins, zc0, zc1, z0, slab_core);
            e.report("field slab " + std::to_string(k + 1) + "/" + std::to_string(slab.slabs));
            return;
        }
        const std::size_t slab_bytes = sp.field_floats() * sizeof(float);
        e.commands.begin();
        if (host_gaussian)
            e.density.record(e.commands, arena, bins, sp, field);  // filtered below, on the host
        else
            e.record_field(arena, sp, &bins, &features, options.filter, field);
        const Buffer& host =
            readback_buffer(e.context, e.commands, arena, field, slab_bytes, "field_readback");
        e.commands.barrier_to_host();
        e.commands.mark("read-field");
        e.commands.submit_and_wait();
        add_times(result.times, e.commands.stage_times());
        e.report("field slab " + std::to_string(k + 1) + "/" + std::to_string(slab.slabs));
        host.invalidate();
        const double t_copy = now_ms();
        const float* src = static_cast<const float*>(host.mapped());
        if (host_gaussian) {
            gaussian_filter_planes(src, d[0], d[1], slab.slab_planes, sp.pitch, taps,
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

    // The slab's density on the host, filtered on the host into the core (or, unfiltered, its
    // core planes copied there).
    void density_on_host(const AtomBins& bins, std::int64_t zc0, std::int64_t zc1,
                         std::int64_t z0, std::vector<float>& slab_core) {
        const auto d = plan.info.dims;
        const std::size_t plane = std::size_t(d[0]) * d[1];
        density.resize(plane * slab.slab_planes);
        const double t0 = now_ms();
        density_host(bins, sp, density.data(), d[0]);
        add_times(result.times, {{"density-host", now_ms() - t0, false}});
        const double t1 = now_ms();
        if (host_gaussian) {
            gaussian_filter_planes(density.data(), d[0], d[1], slab.slab_planes, d[0], taps,
                                   std::uint32_t(zc0 - z0), std::uint32_t(zc1 - z0),
                                   slab_core.data(), filter_scratch);
            add_times(result.times, {{"filter-host", now_ms() - t1, false}});
        } else {
            std::copy(density.begin() + (zc0 - z0) * plane, density.begin() + (zc1 - z0) * plane,
                      slab_core.begin());
            add_times(result.times, {{"assemble-field", now_ms() - t1, false}});
        }
    }
};

}  // namespace

SurfaceResult EngineImpl::run_in_slabs(const Atoms& atoms, const SurfaceOptions& options,
                                       GridPlan plan, SurfaceResult result) {
    const auto d = plan.info.dims;
    // Overlap on each side, enough that the filter kernel's reach from outside the slab (and
    // the circular wrap of the slab's FFT) is below float rounding in the core.
    SlabInputs in;
    in.dims = d;
    in.pitch = plan.pitch;
    in.overlap = filter_reach_planes(options, plan);
    in.filtered = plan.filtered;
    in.limit = field_budget();
    in.gather_field = options.refine > 0 && plan.filtered && !plan.exact_ses;
    in.host_memory = physical_memory();
    in.spacing = options.spacing;
    in.atoms = &atoms;
    // Slabs sized for the device's bindings; where the host alone computes and marches the
    // field (the density and filter, or the exact SES, and marching cubes on the host), a grid
    // too wide for those bindings is sized for the host's budget instead (no device buffer
    // holds a slab then).
    const bool host_only = field_only_on_host(options, plan);
    SlabPlan slab;
    try {
        slab = plan_slabs(in);
    } catch (const Error& error) {
        if (!host_only || error.code() != ErrorCode::DeviceLimit ||
            double(in.limit) >= host_field_budget())
            throw;
        in.limit = static_cast<std::uint64_t>(host_field_budget());
        slab = plan_slabs(in);
    }
    result.grid.slabs = slab.slabs;

    // Density and filter, slab by slab. Each slab's core planes come back to the host, and
    // marching cubes runs on the cells of slab k's core once slab k + 1's first planes are in:
    // its top cells and the gradients there (one extra plane on both sides, so that the normals
    // equal those of a single pass) need them. The host keeps only the core whose cells are
    // pending (and the one just read) and the plane under it; the whole field is gathered only
    // for refinement of the filtered SES, which reads it anywhere (1.3 GB for the 686³ grid of
    // the 4YVS assembly). The slab buffer stays while marching cubes runs on the earlier cores
    // (one more buffer of at most field_budget() beside marching cubes' own; released before
    // the last).
    const std::size_t plane_floats = std::size_t(d[0]) * d[1];
    std::vector<float> full(in.gather_field ? plane_floats * d[2] : 0);
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
        // The host's index of them is part of the stage, as on one grid (engine.cpp).
        if (host_ses || snaps(options, plan) || options.refine > 0)
            ses = std::make_unique<SesHostField>(features, plan.ses_d_max);
        add_times(result.times, {{"ses-features", now_ms() - t0, false}});
    }
    result.grid.host_ses_distance = host_ses;
    SlabMarcher marcher{*this, plan, result};
    marcher.core = slab.core;
    marcher.host_mc = on_host(marching_cubes_place);
    marcher.plane_floats = plane_floats;
    marcher.mc_plane_bytes = std::uint64_t(d[0]) * d[1] * sizeof(float);
    if (!atoms.empty()) {
        double z0 = atoms.xyz[2] - atoms.radius[0], z1 = atoms.xyz[2] + atoms.radius[0];
        for (std::size_t i = 1; i < atoms.size(); ++i) {
            z0 = std::min(z0, double(atoms.xyz[3 * i + 2]) - atoms.radius[i]);
            z1 = std::max(z1, double(atoms.xyz[3 * i + 2]) + atoms.radius[i]);
        }
        const double h = plan.info.spacing;
        marcher.surface_z0 = (z0 - options.probe - plan.info.origin[2]) / h;
        marcher.surface_z1 = (z1 + options.probe - plan.info.origin[2]) / h;
    }
    result.grid.host_marching_cubes = marcher.host_mc;
    SlabFields fields{*this, atoms, options, plan, features, ses.get(), result, slab};
    fields.host_ses = host_ses;
    fields.host_gaussian = gaussian_on_host(options, plan);
    if (fields.host_gaussian) fields.taps = host_gaussian_taps(options, plan);
    fields.host_density = density_on_host(options, plan);
    result.grid.host_filter = fields.host_gaussian;
    result.grid.host_density = fields.host_density;
    fields.sp = plan;
    fields.sp.info.dims[2] = slab.slab_planes;
    if (!host_ses && !fields.host_density)
        fields.field = Buffer(context, fields.sp.field_floats() * sizeof(float), MemoryUse::Device,
                              "field_slab");
    std::vector<float> slab_core;  // two core buffers, swapped: pages touched once, not per slab
    for (std::uint32_t k = 0; k < slab.slabs; ++k) {
        const std::int64_t zc0 = std::int64_t(k) * slab.core;
        const std::int64_t zc1 = std::min<std::int64_t>(zc0 + slab.core, d[2]);
        const std::size_t core_floats = std::size_t(zc1 - zc0) * plane_floats;
        if (slab_core.size() < core_floats) {
            // Fresh pages (the first two cores, 125 MB each on the 2.43 M-atom shell at 1 Å)
            // on all threads, before resize zeroes them on one.
            slab_core.reserve(core_floats);
            populate_pages({room_up_to(slab_core, core_floats)});
        }
        slab_core.resize(core_floats);
        fields.compute(k, slab_core);
        if (!full.empty())
            std::copy(slab_core.begin(), slab_core.end(), full.begin() + zc0 * plane_floats);
        // The slab buffer is released before marching cubes on the last cores allocates its
        // buffers (the earlier parts run beside it).
        if (k + 1 == slab.slabs) {
            fields.field = Buffer();
            if (host_ses) ses->release_scratch();  // the field's, kept from slab to slab
        }
        if (k > 0) {
            marcher.march(slab_core);
            marcher.below.assign(marcher.pending.end() - plane_floats, marcher.pending.end());
        }
        std::swap(marcher.pending, slab_core);
        marcher.pending_z0 = std::uint32_t(zc0);
    }
    marcher.march({});
    marcher.part_field = Buffer();
    // Freed, not just emptied (`= {}` keeps a vector's capacity): the two cores' 0.25 GB on the
    // 2.43 M-atom shell at 1 Å go to what the snap allocates (the host index's bin lists).
    std::vector<float>().swap(marcher.pending);
    std::vector<float>().swap(slab_core);
    std::vector<float>().swap(marcher.below);
    // The seams were stitched as the parts came in: the stage is their time.
    result.mesh = std::move(marcher.mesh);
    result.times.push_back({"stitch", marcher.stitch_ms, false});
    report("stitch");
    const FieldView view{full.data(), d[0], d[1], d[2], d[0]};
    host_stages(result, atoms, options, plan, ses.get(), nullptr, full.empty() ? nullptr : &view);
    return result;
}

}  // namespace fdmsurf::detail
