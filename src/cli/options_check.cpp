// The checks of the fdmsurf program's option combinations, once every argument is read: the
// options that exclude each other, need each other or need an INPUT or an OUTPUT, each failure
// an Error(InvalidArgument) naming them (exit 2, before any work).
#include "cli/options_check.hpp"

#include <algorithm>
#include <cstddef>

#include "cli/models_table.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::cli {
namespace {

[[noreturn]] void fail(const std::string& message) {
    throw Error(ErrorCode::InvalidArgument, message);
}

// --models all against --model N, --method edt against the settings of the FDM method; then
// --paper's settings where no option says otherwise, wherever it stands.
void settle_method(CliOptions& o, const ArgumentsSeen& seen) {
    if (o.all_models) {
        if (seen.explicit_model) fail("--model N and --models all exclude each other");
        o.read.model = fdmsurf::kAllModels;
    }
    if (o.surface.method == SesMethod::Edt) {
        if (o.surface.surface != SurfaceKind::Ses)
            fail(
                "--method edt is a way to compute the ses surface; it does not apply to "
                "--surface " +
                std::string(surface_name(o.surface.surface)));
        if (o.paper)
            fail("--paper selects the paper's FDM settings; it cannot go with --method edt");
        if (!seen.fdm_only.empty())
            fail(seen.fdm_only +
                 " is a setting of the FDM method; --method edt (the exact SES) has no filter, "
                 "density or level to set");
    }
    if (o.paper) {
        // The paper's settings, except where an option says otherwise, wherever it stands.
        const fdmsurf::SurfaceOptions paper = fdmsurf::paper_settings(o.surface);
        if (!o.explicit_filter) o.surface.filter = paper.filter;
        if (!o.explicit_level) o.surface.level = paper.level;
        if (!o.explicit_cavities) o.surface.min_cavity_volume = paper.min_cavity_volume;
    }
}

// --relative and --buried need --areas; --areas needs one structure, and a mesh for ses.
void check_areas(const CliOptions& o) {
    if (o.areas.empty()) {
        if (o.relative != RelativeTable::None)
            fail("--relative divides the per-residue areas of --areas FILE: give --areas too");
        if (!o.buried.empty())
            fail("--buried writes the buried areas into --areas FILE: give --areas too");
        return;
    }
    if (o.all_models) {
        // The table of every model (cli/models_table.hpp): the exact SASA needs no mesh.
        if (o.inputs.size() > 1)
            fail("--models all --areas writes one table of one INPUT's models: give one INPUT");
        if (o.relative != RelativeTable::None || !o.buried.empty())
            fail("--relative and --buried write one structure's areas file; with --models all, "
                 "--areas writes the table of the models");
        return;
    }
    if (is_jsonl_path(o.areas))
        fail("--areas FILE.jsonl is the table of --models all; one structure's areas go to a "
             ".csv or .json file");
    if (o.inputs.size() > 1)
        fail("--areas writes one file for one structure: give one INPUT (or --models all for "
             "a table of its models)");
    if (o.output.empty() && o.surface.surface == SurfaceKind::Ses)
        fail(
            "--areas without -o computes no mesh, which the ses areas come from (the "
            "vdw and sas areas are exact without one): give -o OUTPUT, or --surface sas");
    if (!o.buried.empty() && !o.patch.empty())
        fail("--buried compares whole surfaces; it cannot go with --patch");
    if (!o.buried.empty() && o.simplify_requested)
        fail(
            "--buried compares the full surfaces; it cannot go with --simplify or "
            "--max-triangles");
    if (!o.output.empty() && o.output != kStdio && o.output == o.areas)
        fail("--areas and -o name the same file '" + o.areas + "'");
}

// --areas without -o: the exact sphere patches, no mesh and no device; nothing that acts on
// a mesh or draws one.
void check_areas_only(const CliOptions& o) {
    if (o.simplify_requested || o.optimize || !o.patch.empty() || o.surface.refine != 0)
        fail(
            "--simplify, --max-triangles, --optimize, --patch and --refine act on the mesh; "
            "without -o none is computed");
    if (!o.image.empty() || !o.render_options_given.empty())
        fail((o.image.empty() ? o.render_options_given : std::string("--image")) +
             " draws the mesh; --areas without -o computes none: give -o FILE.png or "
             "-o OUTPUT --image FILE.png");
}

// -o FILE.png, --image and the options that set up a picture.
void check_pictures(const CliOptions& o) {
    if (o.image_output) {
        if (!o.image.empty())
            fail("-o '" + o.output + "' already writes the picture; --image adds one beside a "
                 "mesh output (.ply, .obj, .glb, .stl or .off)");
        if (o.output == kStdio && o.views.size() > 1)
            fail("-o - writes one picture to standard output: give one --view");
    }
    if (!o.image.empty()) {
        if (o.image == kStdio)
            fail("--image writes files; for a picture on standard output use -o - "
                 "--output-format png");
        if (!is_png_path(o.image) && !output_is_folder(o.image))
            fail("--image must name a .png file or a folder (ending in '/'), got '" + o.image +
                 "'");
        if ((o.inputs.size() > 1 || o.all_models) && !output_is_folder(o.image))
            fail("several INPUTs or models need --image to name a folder (ending in '/'), got '" +
                 o.image + "'");
    }
    if (!o.wants_images() && !o.render_options_given.empty())
        fail(o.render_options_given +
             " sets up a picture: write one with -o FILE.png or --image FILE.png");
}

// The INPUTs against OUTPUT: standard input at most once, one INPUT to standard output, a
// folder for several INPUTs or models, no two INPUTs writing one file.
void check_inputs(const CliOptions& o) {
    if (std::count(o.inputs.begin(), o.inputs.end(), kStdio) > 1)
        fail("'-' (standard input) is given more than once");
    if (o.output == kStdio && o.inputs.size() > 1)
        fail("-o - writes one mesh to standard output: give one INPUT, or -o FOLDER/");
    if (o.inputs.size() > 1 && !output_is_folder(o.output))
        fail("several INPUTs need -o to name a folder (ending in '/'), got '" + o.output + "'");
    if (o.all_models && !output_is_folder(o.output))
        fail(
            "--models all writes one mesh per model (NAME-mN.ply): -o must name a folder "
            "(ending in '/'), got '" +
            o.output + "'");
    for (std::size_t i = 0; i < o.inputs.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (primary_output(o, o.inputs[i], 1) == primary_output(o, o.inputs[j], 1))
                fail("inputs '" + o.inputs[j] + "' and '" + o.inputs[i] + "' would both write '" +
                     primary_output(o, o.inputs[i], 1) + "'");
}

}  // namespace

void check_combinations(CliOptions& o, const ArgumentsSeen& seen) {
    settle_method(o, seen);
    if (o.list_devices && !o.help && !o.version && !o.inputs.empty())
        fail("--list-devices takes no INPUT (got '" + o.inputs.front() + "')");
    if (o.help || o.version || o.list_devices) return;
    if (o.inputs.empty()) fail("missing INPUT, the structure file to read; see fdmsurf --help");
    check_areas(o);
    if (o.simplifier_given && !o.simplify_requested)
        fail("--simplifier chooses how --simplify or --max-triangles simplify: give one of them");
    if (o.output.empty() && !o.areas.empty()) {
        check_areas_only(o);  // areas only: the exact sphere patches, no mesh and no device
        return;
    }
    if (o.output.empty())
        fail(
            "missing -o OUTPUT, the mesh file to write (.ply, .obj, .glb, .stl or .off; - for "
            "standard output) or the picture (.png)");
    // A .png OUTPUT is a picture, whatever else; --output-format png names one too.
    if (o.output_format == MeshFormat::Auto && is_png_path(o.output)) o.image_output = true;
    check_pictures(o);
    check_inputs(o);
}

}  // namespace fdmsurf::cli
