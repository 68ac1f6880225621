// The engine's test hooks (engine_impl.hpp): one stage at a time on the device, so that the
// tests compare each GPU stage with its CPU reference.
#include <cstring>
#include <vector>

#include "engine/engine_impl.hpp"
#include "engine/engine_steps.hpp"

namespace fdmsurf::detail {

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

}  // namespace fdmsurf::detail
