// The engine (Giard & Macq 2010: density, spectral filter, marching cubes, on one device): the
// public Engine, and EngineImpl::run, which plans the grid, checks it (preflight.cpp) and hands
// the surface to one of three paths: slabs for a field larger than one buffer (slabs.cpp), the
// host's marching cubes (host_path.cpp) or the device's (device_path.cpp). The host stages after
// marching cubes (snap, refine) follow in snap_stage.cpp and refine_stage.cpp.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>

#include "base/trace.hpp"
#include "engine/engine_impl.hpp"
#include "engine/engine_steps.hpp"
#include "engine/preflight.hpp"
#include "fdmsurf/fdmsurf.hpp"
#include "grid/atom_bins.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "mesh/cavities.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "properties/vertex_properties.hpp"
#include "refine/refine.hpp"
#include "vulkan/check.hpp"
#include "vulkan/commands.hpp"
#include "vulkan/context.hpp"

namespace fdmsurf {
namespace detail {

SurfaceResult EngineImpl::run(const Atoms& atoms, const SurfaceOptions& options,
                              GpuMesh* on_device) {
    SurfaceResult result;
    const double t0 = now_ms();
    check_refine_levels(options.refine);
    trace("engine: run");
    GridPlan plan = plan_grid(atoms, options);
    result.grid = plan.info;
    trace("engine: grid planned");
    result.warnings = preflight_warnings(atoms, options, plan);
    const double field_bytes = double(plan.field_floats()) * sizeof(float);
    if (field_bytes > one_piece_limit(options, plan, on_device != nullptr)) {
        result = run_in_slabs(atoms, options, plan, std::move(result));
        if (on_device) *on_device = upload_mesh(result.mesh);
        return result;
    }
    FieldSources sources;
    find_field_sources(atoms, options, plan, on_device != nullptr, t0, sources, result);
    if (sources.host_mc) return run_on_host(atoms, options, plan, sources, std::move(result));
    return run_on_device(atoms, options, plan, sources, on_device, std::move(result));
}

void EngineImpl::find_field_sources(const Atoms& atoms, const SurfaceOptions& options,
                                    const GridPlan& plan, bool on_device, double t0,
                                    FieldSources& src, SurfaceResult& result) {
    const auto& d = plan.info.dims;
    // The exact SES field on the host (EngineOptions::ses_distance; not for a mesh left on the
    // device): computed here, uploaded only where marching cubes runs on the device.
    src.host_mc = !on_device && on_host(marching_cubes_place);
    src.host_ses = plan.exact_ses && !on_device && on_host(ses_distance_place);
    result.grid.host_ses_distance = src.host_ses;
    // The host's index of the features (part of the stage): for the field on the host, the snap
    // and refinement.
    if (plan.exact_ses) {
        src.features = build_ses_features(atoms, options.probe);
        if (src.host_ses || snaps(options, plan) || options.refine > 0)
            src.ses = std::make_unique<SesHostField>(src.features, plan.ses_d_max);
        result.times.push_back({"ses-features", now_ms() - t0, false});
    } else {
        // The host's density pass (run_on_host) needs no distances to non-empty bins.
        src.bins = bin_atoms(atoms, plan, !(src.host_mc && density_on_host(options, plan)));
        result.times.push_back({"bin-atoms", now_ms() - t0, false});
    }
    report(plan.exact_ses ? "ses-features" : "bin-atoms");
    trace(plan.exact_ses ? "engine: ses features" : "engine: atoms binned");
    // The host's exact SES field, in the plan's layout: written once by the evaluation (fresh
    // pages, first touched on its threads; no zero-fill before).
    if (src.host_ses) {
        const double t_ses = now_ms();
        src.host_values.reset(new float[plan.field_floats()]);
        if (plan.pitch > d[0]) std::fill_n(src.host_values.get(), plan.field_floats(), 0.0f);
        src.ses->evaluate(plan, 0, d[2], src.host_values.get(), plan.pitch);
        src.ses->release_scratch();
        add_times(result.times, {{"ses-host", now_ms() - t_ses, false}});
        report("ses-host");
    }
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
    const bool ses = options.surface == SurfaceKind::Ses;
    const bool fdm = ses && options.method == SesMethod::Fdm;
    // The pieces and their statistics, found once when the statistics are asked for (those of
    // the pieces kept), or when both removals read them; a single removal alone finds its own.
    const bool specks = ses && !fdm;
    const bool cavities =
        options.min_cavity_volume > 0.0f || (options.min_cavity_volume < 0.0f && fdm);
    std::optional<detail::MeshAnalysis> analysis;
    if ((options.mesh_stats || (specks && cavities)) && result.mesh.triangle_count() > 0) {
        const double t_pieces = detail::now_ms();
        analysis = detail::analyse_mesh(result.mesh, options.mesh_stats, "remove_cavities");
        result.times.push_back({"pieces", detail::now_ms() - t_pieces, false});
        impl_->report("pieces");
        detail::trace("engine: pieces");
    }
    const double t0 = detail::now_ms();
    detail::MeshAnalysis* const pieces = analysis ? &*analysis : nullptr;
    if (specks) {
        // The exact SES touches itself at isolated points (where probes meet around a tiny
        // unswept gap); the grid turns some into closed specks far smaller than a cell.
        const double h = options.spacing;
        result.specks_removed = detail::remove_specks(result.mesh, h * h * h, pieces);
    }
    if (options.min_cavity_volume >= 0.0f) {
        if (options.min_cavity_volume > 0.0f)
            result.cavities_removed =
                detail::remove_cavities_below(result.mesh, options.min_cavity_volume, pieces);
    } else if (fdm) {
        // A void is part of the SES only if the probe fits in it; the filter also opens voids
        // where it does not (and closes some where it does).
        result.cavities_removed =
            detail::remove_cavities_without_probe(result.mesh, atoms, options.probe, pieces);
    }
    // (By default the exact SES, vdw and sas keep every cavity.)
    if (result.mesh.triangle_count() == 0 && !atoms.empty())
        result.warnings.push_back(empty_surface_warning(atoms, options));
    result.times.push_back({"cavities", detail::now_ms() - t0, false});
    impl_->report("cavities");
    detail::trace("engine: cavities");
    if (options.mesh_stats)
        result.stats =
            analysis ? detail::total_stats(*analysis, result.mesh) : compute_stats(result.mesh);
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
