// Tests of the command-line parser: every option, both value spellings, every rejected input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <vulkan/vulkan_core.h>

#include "cli/options.hpp"
#include "cli/usage.hpp"

namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::FilterShape;
using fdmsurf::StructureFormat;
using fdmsurf::SurfaceKind;
using fdmsurf::cli::CliOptions;
using fdmsurf::cli::parse_args;

// The arguments of a normal run followed by `extra`.
CliOptions parse_with(std::vector<std::string> extra) {
    std::vector<std::string> args{"in.pdb", "-o", "out.ply"};
    args.insert(args.end(), extra.begin(), extra.end());
    return parse_args(args);
}

// The message of the InvalidArgument error that parse_args throws, or a failure.
std::string parse_error(const std::vector<std::string>& args) {
    try {
        parse_args(args);
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error thrown";
    return {};
}

std::string parse_error_with(std::vector<std::string> extra) {
    std::vector<std::string> args{"in.pdb", "-o", "out.ply"};
    args.insert(args.end(), extra.begin(), extra.end());
    return parse_error(args);
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(CliOptions, DefaultsAreTheLibraryDefaults) {
    const CliOptions o = parse_args({"in.pdb", "-o", "out.ply"});
    ASSERT_EQ(o.inputs.size(), 1u);
    EXPECT_EQ(o.inputs[0], "in.pdb");
    EXPECT_EQ(o.output, "out.ply");
    const fdmsurf::SurfaceOptions s;
    EXPECT_EQ(o.surface.surface, s.surface);
    EXPECT_EQ(o.surface.spacing, s.spacing);
    EXPECT_EQ(o.surface.probe, s.probe);
    EXPECT_EQ(o.surface.cutoff, s.cutoff);
    EXPECT_EQ(o.surface.sigma, s.sigma);
    EXPECT_EQ(o.surface.level, s.level);
    EXPECT_EQ(o.surface.filter, s.filter);
    EXPECT_EQ(o.surface.padding, s.padding);
    const fdmsurf::ReadOptions r;
    EXPECT_EQ(o.read.format, r.format);
    EXPECT_EQ(o.read.model, r.model);
    EXPECT_EQ(o.read.keep_waters, r.keep_waters);
    EXPECT_EQ(o.read.keep_hydrogens, r.keep_hydrogens);
    EXPECT_EQ(o.read.keep_ligands, r.keep_ligands);
    EXPECT_TRUE(o.engine.device.empty());
    EXPECT_FALSE(o.engine.validation);
    EXPECT_FALSE(o.list_devices);
    EXPECT_FALSE(o.quiet);
    EXPECT_FALSE(o.json);
    EXPECT_FALSE(o.help);
    EXPECT_FALSE(o.version);
}

TEST(CliOptions, OutputSpellings) {
    EXPECT_EQ(parse_args({"in.pdb", "-o", "a.obj"}).output, "a.obj");
    EXPECT_EQ(parse_args({"-o", "a.obj", "in.pdb"}).output, "a.obj");
    EXPECT_EQ(parse_args({"in.pdb", "--output", "b.ply"}).output, "b.ply");
    EXPECT_EQ(parse_args({"in.pdb", "--output=c.ply"}).output, "c.ply");
    EXPECT_EQ(parse_args({"in.pdb", "--output=d=e.ply"}).output, "d=e.ply");
}

TEST(CliOptions, SurfaceKinds) {
    EXPECT_EQ(parse_with({"--surface", "ses"}).surface.surface, SurfaceKind::Ses);
    EXPECT_EQ(parse_with({"--surface", "vdw"}).surface.surface, SurfaceKind::Vdw);
    EXPECT_EQ(parse_with({"--surface=sas"}).surface.surface, SurfaceKind::Sas);
    EXPECT_EQ(parse_with({"--surface", "SES"}).surface.surface, SurfaceKind::Ses);
}

TEST(CliOptions, NumericOptionsInBothSpellings) {
    const CliOptions a = parse_with({"--spacing", "0.25", "--probe", "1.2", "--cutoff", "0.2",
                                     "--sigma", "2.5", "--level", "0.8", "--padding", "4"});
    EXPECT_FLOAT_EQ(a.surface.spacing, 0.25f);
    EXPECT_FLOAT_EQ(a.surface.probe, 1.2f);
    EXPECT_FLOAT_EQ(a.surface.cutoff, 0.2f);
    EXPECT_FLOAT_EQ(a.surface.sigma, 2.5f);
    EXPECT_FLOAT_EQ(a.surface.level, 0.8f);
    EXPECT_FLOAT_EQ(a.surface.padding, 4.0f);
    const CliOptions b = parse_with(
        {"--spacing=0.75", "--probe=0", "--cutoff=0", "--sigma=1e1", "--level=+2", "--padding=0"});
    EXPECT_FLOAT_EQ(b.surface.spacing, 0.75f);
    EXPECT_FLOAT_EQ(b.surface.probe, 0.0f);
    EXPECT_FLOAT_EQ(b.surface.cutoff, 0.0f);
    EXPECT_FLOAT_EQ(b.surface.sigma, 10.0f);
    EXPECT_FLOAT_EQ(b.surface.level, 2.0f);
    EXPECT_FLOAT_EQ(b.surface.padding, 0.0f);
}

TEST(CliOptions, LastValueWins) {
    EXPECT_FLOAT_EQ(parse_with({"--spacing", "1", "--spacing=0.3"}).surface.spacing, 0.3f);
}

TEST(CliOptions, Filters) {
    EXPECT_EQ(parse_with({"--filter", "ideal"}).surface.filter, FilterShape::Ideal);
    EXPECT_EQ(parse_with({"--filter=gaussian"}).surface.filter, FilterShape::Gaussian);
}

TEST(CliOptions, Model) {
    EXPECT_EQ(parse_with({"--model", "3"}).read.model, 3);
    EXPECT_EQ(parse_with({"--model=1"}).read.model, 1);
}

TEST(CliOptions, ModelsAllNeedsAFolder) {
    const CliOptions o = parse_args({"in.pdb", "--models", "all", "-o", "meshes/"});
    EXPECT_TRUE(o.all_models);
    EXPECT_EQ(o.read.model, fdmsurf::kAllModels);
    EXPECT_TRUE(parse_args({"in.pdb", "--models=ALL", "-o", "meshes/"}).all_models);
    EXPECT_FALSE(parse_with({}).all_models);
    const std::string file = parse_error_with({"--models", "all"});
    EXPECT_TRUE(contains(file, "--models all")) << file;
    EXPECT_TRUE(contains(file, "folder")) << file;
    EXPECT_TRUE(contains(file, "out.ply")) << file;
    const std::string value = parse_error({"in.pdb", "--models", "2", "-o", "m/"});
    EXPECT_TRUE(contains(value, "'2'")) << value;
    EXPECT_TRUE(contains(value, "expected all")) << value;
    const std::string both = parse_error({"in.pdb", "--model", "2", "--models", "all", "-o", "m/"});
    EXPECT_TRUE(contains(both, "--model N and --models all")) << both;
    EXPECT_TRUE(contains(parse_error({"in.pdb", "--models", "-o", "m/"}), "needs a value"));
}

TEST(CliOptions, ModelOutputNames) {
    using fdmsurf::cli::output_for;
    EXPECT_EQ(output_for("data/1d3z.pdb.gz", "meshes/", 3), "meshes/1d3z-m3.ply");
    EXPECT_EQ(output_for("x.cif", "out/", 10), "out/x-m10.ply");
    // .gz in any case, as format detection reads it.
    EXPECT_EQ(output_for("h.PDB.GZ", "out/", 1), "out/h-m1.ply");
    EXPECT_EQ(output_for("h.cif.Gz", "out/", 2), "out/h-m2.ply");
}

TEST(CliOptions, Assembly) {
    EXPECT_EQ(parse_with({}).read.assembly, 0);
    EXPECT_EQ(parse_with({"--assembly", "1"}).read.assembly, 1);
    EXPECT_EQ(parse_with({"--assembly=0"}).read.assembly, 0);
    const std::string negative = parse_error_with({"--assembly", "-1"});
    EXPECT_TRUE(contains(negative, "--assembly")) << negative;
    EXPECT_TRUE(contains(negative, ">= 0")) << negative;
    EXPECT_TRUE(contains(parse_error_with({"--assembly", "one"}), "not a whole number"));
}

TEST(CliOptions, SelectionFlags) {
    const CliOptions o = parse_with({"--waters", "--hydrogens", "--no-ligands"});
    EXPECT_TRUE(o.read.keep_waters);
    EXPECT_TRUE(o.read.keep_hydrogens);
    EXPECT_FALSE(o.read.keep_ligands);
}

TEST(CliOptions, Formats) {
    EXPECT_EQ(parse_with({"--format", "pdb"}).read.format, StructureFormat::Pdb);
    EXPECT_EQ(parse_with({"--format", "cif"}).read.format, StructureFormat::Mmcif);
    EXPECT_EQ(parse_with({"--format", "mmcif"}).read.format, StructureFormat::Mmcif);
    EXPECT_EQ(parse_with({"--format", "pqr"}).read.format, StructureFormat::Pqr);
    EXPECT_EQ(parse_with({"--format=xyzr"}).read.format, StructureFormat::Xyzr);
}

TEST(CliOptions, DeviceByIndexOrName) {
    EXPECT_EQ(parse_with({"--device", "1"}).engine.device, "1");
    EXPECT_EQ(parse_with({"--device=llvmpipe"}).engine.device, "llvmpipe");
    EXPECT_EQ(parse_with({"--device", "NVIDIA GeForce"}).engine.device, "NVIDIA GeForce");
}

TEST(CliOptions, HostStagesAutoOnOrOff) {
    using fdmsurf::StagePlace;
    const CliOptions none = parse_with({});
    EXPECT_EQ(none.engine.gaussian_filter, StagePlace::Auto);
    EXPECT_EQ(none.engine.marching_cubes, StagePlace::Auto);
    EXPECT_EQ(parse_with({"--host-filter", "on"}).engine.gaussian_filter, StagePlace::Host);
    EXPECT_EQ(parse_with({"--host-filter=off"}).engine.gaussian_filter, StagePlace::Device);
    EXPECT_EQ(parse_with({"--host-mc", "on"}).engine.marching_cubes, StagePlace::Host);
    EXPECT_EQ(parse_with({"--host-mc=OFF"}).engine.marching_cubes, StagePlace::Device);
    EXPECT_EQ(parse_with({"--host-mc", "off", "--host-mc", "auto"}).engine.marching_cubes,
              StagePlace::Auto);
    EXPECT_EQ(none.engine.vertex_atoms, StagePlace::Auto);
    EXPECT_EQ(parse_with({"--host-atoms", "off"}).engine.vertex_atoms, StagePlace::Device);
    EXPECT_EQ(parse_with({"--host-atoms=on"}).engine.vertex_atoms, StagePlace::Host);
    EXPECT_TRUE(contains(parse_error_with({"--host-atoms", "maybe"}), "auto, on or off"));
    EXPECT_EQ(none.engine.ses_distance, StagePlace::Auto);
    EXPECT_EQ(parse_with({"--host-ses", "off"}).engine.ses_distance, StagePlace::Device);
    EXPECT_EQ(parse_with({"--host-ses=on"}).engine.ses_distance, StagePlace::Host);
    EXPECT_TRUE(contains(parse_error_with({"--host-ses", "yes"}), "--host-ses"));
    EXPECT_EQ(none.engine.density, StagePlace::Auto);
    EXPECT_EQ(parse_with({"--host-density", "off"}).engine.density, StagePlace::Device);
    EXPECT_EQ(parse_with({"--host-density=on"}).engine.density, StagePlace::Host);
    EXPECT_TRUE(contains(parse_error_with({"--host-density", "gpu"}), "--host-density"));
    const std::string message = parse_error_with({"--host-mc", "gpu"});
    EXPECT_TRUE(contains(message, "--host-mc")) << message;
    EXPECT_TRUE(contains(message, "auto, on or off")) << message;
    EXPECT_TRUE(contains(parse_error_with({"--host-mc"}), "--host-mc needs a value"));
    const std::string help = fdmsurf::cli::usage_text();
    EXPECT_TRUE(contains(help, "--host-filter auto|on|off")) << help;
    EXPECT_TRUE(contains(help, "--host-mc auto|on|off")) << help;
    EXPECT_TRUE(contains(help, "--host-atoms auto|on|off")) << help;
    EXPECT_TRUE(contains(help, "--host-ses auto|on|off")) << help;
    EXPECT_TRUE(contains(help, "--host-density auto|on|off")) << help;
}

TEST(CliOptions, OutputFlags) {
    const CliOptions o = parse_with({"--stats", "json", "--quiet", "--validation"});
    EXPECT_TRUE(o.json);
    EXPECT_TRUE(o.quiet);
    EXPECT_TRUE(o.engine.validation);
    EXPECT_TRUE(parse_with({"--stats=json"}).json);
    EXPECT_FALSE(parse_with({"--stats=json", "--stats", "text"}).json);
}

TEST(CliOptions, HelpVersionAndListDevicesNeedNoInput) {
    EXPECT_TRUE(parse_args({"--help"}).help);
    EXPECT_TRUE(parse_args({"-h"}).help);
    EXPECT_TRUE(parse_args({"--version"}).version);
    EXPECT_TRUE(parse_args({"--list-devices"}).list_devices);
    EXPECT_TRUE(parse_args({"in.pdb", "--help"}).help);
}

TEST(CliOptions, DoubleDashEndsOptions) {
    const CliOptions o = parse_args({"-o", "out.ply", "--", "-strange name.pdb"});
    ASSERT_EQ(o.inputs.size(), 1u);
    EXPECT_EQ(o.inputs[0], "-strange name.pdb");
}

TEST(CliOptions, UnknownOptionSuggestsHelp) {
    const std::string message = parse_error_with({"--bogus"});
    EXPECT_TRUE(contains(message, "unknown option '--bogus'")) << message;
    EXPECT_TRUE(contains(message, "--help")) << message;
    EXPECT_TRUE(contains(parse_error_with({"-x"}), "'-x'"));
    EXPECT_TRUE(contains(parse_error_with({"--bogus=1"}), "'--bogus'"));
}

TEST(CliOptions, UnknownOptionNearAKnownOneIsCorrected) {
    const std::string message = parse_error_with({"--spaceing", "1"});
    EXPECT_TRUE(contains(message, "did you mean --spacing?")) << message;
    EXPECT_FALSE(contains(parse_error_with({"--zzzzzzzz"}), "did you mean"));
}

TEST(CliOptions, MissingValue) {
    for (const char* option :
         {"--spacing", "--probe", "--cutoff", "--sigma", "--level", "--padding", "--model",
          "--surface", "--filter", "--format", "--device", "--stats", "--output"}) {
        const std::string message = parse_error_with({option});
        EXPECT_TRUE(contains(message, std::string(option) + " needs a value")) << message;
    }
    EXPECT_TRUE(contains(parse_error({"in.pdb", "-o"}), "-o needs a value"));
    EXPECT_TRUE(contains(parse_error_with({"--spacing="}), "--spacing needs a value"));
    // The next option is not taken as the value.
    EXPECT_TRUE(contains(parse_error({"in.pdb", "-o", "--quiet"}), "-o needs a value"));
    EXPECT_TRUE(contains(parse_error_with({"--spacing", "--quiet"}), "needs a value"));
    EXPECT_TRUE(contains(parse_error_with({"--device", "-h"}), "needs a value"));
}

TEST(CliOptions, FlagWithValue) {
    const std::string message = parse_error_with({"--quiet=yes"});
    EXPECT_TRUE(contains(message, "--quiet takes no value")) << message;
}

TEST(CliOptions, NonNumeric) {
    for (const char* value : {"abc", "1.5x", "0x10", " 1", "1 ", "--", "1e", "."}) {
        const std::string message = parse_error_with({std::string("--spacing=") + value});
        EXPECT_TRUE(contains(message, "--spacing")) << message;
        EXPECT_TRUE(contains(message, "not a number")) << message;
    }
    EXPECT_TRUE(contains(parse_error_with({"--probe", "one"}), "'one' is not a number"));
    EXPECT_TRUE(contains(parse_error_with({"--model", "1.5"}), "not a whole number"));
    EXPECT_TRUE(contains(parse_error_with({"--model", "two"}), "not a whole number"));
}

TEST(CliOptions, NanAndInfinity) {
    for (const char* option :
         {"--spacing", "--probe", "--cutoff", "--sigma", "--level", "--padding"}) {
        for (const char* value : {"nan", "NaN", "inf", "-inf", "infinity"}) {
            const std::string message = parse_error_with({option, value});
            EXPECT_TRUE(contains(message, option)) << message;
            EXPECT_TRUE(contains(message, "not a finite number")) << message;
        }
    }
}

TEST(CliOptions, OutOfRangeNumbers) {
    EXPECT_TRUE(contains(parse_error_with({"--spacing", "1e40"}), "out of range"));
    EXPECT_TRUE(contains(parse_error_with({"--model", "99999999999"}), "out of range"));
}

TEST(CliOptions, RangeChecks) {
    struct Case {
        const char* option;
        const char* value;
        const char* condition;
    };
    for (const Case& c : {Case{"--spacing", "0", "> 0"}, Case{"--spacing", "-0.5", "> 0"},
                          Case{"--probe", "-1", ">= 0"}, Case{"--sigma", "0", "> 0"},
                          Case{"--sigma", "-3", "> 0"}, Case{"--cutoff", "-0.1", ">= 0"},
                          Case{"--model", "0", ">= 1"}, Case{"--model", "-2", ">= 1"},
                          Case{"--level", "0", "> 0"}, Case{"--padding", "-1", ">= 0"}}) {
        const std::string message = parse_error_with({c.option, c.value});
        EXPECT_TRUE(contains(message, std::string(c.option) + " must be " + c.condition))
            << message;
        EXPECT_TRUE(contains(message, std::string("got ") + c.value)) << message;
        // The same with the `=` spelling.
        EXPECT_TRUE(
            contains(parse_error_with({std::string(c.option) + "=" + c.value}), " must be "));
    }
}

TEST(CliOptions, UnknownChoices) {
    const std::string surface = parse_error_with({"--surface", "xyz"});
    EXPECT_TRUE(contains(surface, "unknown surface kind 'xyz'")) << surface;
    EXPECT_TRUE(contains(surface, "ses, vdw or sas")) << surface;
    EXPECT_TRUE(contains(parse_error_with({"--filter", "box"}), "unknown filter 'box'"));
    EXPECT_TRUE(contains(parse_error_with({"--format", "xyz"}), "unknown input format 'xyz'"));
    EXPECT_TRUE(contains(parse_error_with({"--stats", "yaml"}), "'yaml'"));
}

TEST(CliOptions, MissingInput) {
    EXPECT_TRUE(contains(parse_error({"-o", "out.ply"}), "missing INPUT"));
    EXPECT_TRUE(contains(parse_error({}), "missing INPUT"));
}

TEST(CliOptions, MissingOutput) {
    EXPECT_TRUE(contains(parse_error({"in.pdb"}), "missing -o OUTPUT"));
}

TEST(CliOptions, SeveralInputsNeedAnOutputFolder) {
    const std::string message = parse_error({"a.pdb", "b.pdb", "-o", "out.ply"});
    EXPECT_TRUE(contains(message, "several INPUTs")) << message;
    EXPECT_TRUE(contains(message, "folder")) << message;
    const CliOptions o = parse_args({"a.pdb", "dir/b.cif.gz", "-o", "meshes/"});
    ASSERT_EQ(o.inputs.size(), 2u);
    EXPECT_EQ(fdmsurf::cli::output_for(o.inputs[1], o.output), "meshes/b.ply");
    EXPECT_TRUE(contains(parse_error({"x/1crn.pdb", "1crn.cif", "-o", "out/"}), "both write"));
    EXPECT_EQ(fdmsurf::cli::output_for("x.pdb", "one.obj"), "one.obj");
}

TEST(CliOptions, PaperSettingsUnlessGivenExplicitly) {
    const CliOptions paper = parse_args({"a.pdb", "-o", "a.ply", "--paper"});
    EXPECT_EQ(paper.surface.filter, fdmsurf::FilterShape::Ideal);
    EXPECT_EQ(paper.surface.level, 1.0f);
    EXPECT_EQ(paper.surface.min_cavity_volume, 0.0f);
    EXPECT_NEAR(fdmsurf::effective_cutoff(paper.surface), 1.0 / (4.0 * 1.4), 1e-6);
    const CliOptions mixed = parse_args({"a.pdb", "--level", "0.95", "-o", "a.ply", "--paper"});
    EXPECT_EQ(mixed.surface.level, 0.95f);
    const CliOptions def = parse_args({"a.pdb", "-o", "a.ply"});
    EXPECT_EQ(def.surface.filter, fdmsurf::FilterShape::Gaussian);
    EXPECT_NEAR(fdmsurf::effective_cutoff(def.surface), 1.3 / (4.0 * 1.4), 1e-6);
    EXPECT_EQ(fdmsurf::effective_level(def.surface), 0.9f);
    const CliOptions none = parse_args({"a.pdb", "-o", "a.ply", "--no-cavities"});
    EXPECT_TRUE(std::isinf(none.surface.min_cavity_volume));
}

TEST(CliOptions, HelpNamesEveryOptionAndExitCode) {
    const std::string help = fdmsurf::cli::usage_text();
    for (const char* option :
         {"--surface",    "--spacing",    "--probe",      "--cutoff",        "--sigma",
          "--level",      "--filter",     "--padding",    "--model",         "--waters",
          "--hydrogens",  "--no-ligands", "--format",     "--device",        "--list-devices",
          "--stats",      "--quiet",      "--validation", "--help",          "--version",
          "--models all", "--assembly N", "-o",           "--method fdm|edt"}) {
        EXPECT_TRUE(contains(help, option)) << option;
    }
    for (const char* text : {"Exit codes", "default 0.5", "default 1.4", "default 3", "Å", "1/Å",
                             "  2  ", "  3  ", "  4  ", "  5  ", "  6  ", "  7  "}) {
        EXPECT_TRUE(contains(help, text)) << text;
    }
}

TEST(CliExitCodes, OnePerErrorClass) {
    using fdmsurf::cli::exit_code_for;
    EXPECT_EQ(exit_code_for(ErrorCode::InvalidArgument), 2);
    EXPECT_EQ(exit_code_for(ErrorCode::Io), 3);
    EXPECT_EQ(exit_code_for(ErrorCode::Format), 3);
    EXPECT_EQ(exit_code_for(ErrorCode::EmptySelection), 3);
    EXPECT_EQ(exit_code_for(ErrorCode::NoDevice), 4);
    EXPECT_EQ(exit_code_for(ErrorCode::DeviceLimit), 4);
    EXPECT_EQ(exit_code_for(ErrorCode::Vulkan), 4);
    EXPECT_EQ(exit_code_for(ErrorCode::Fft), 4);
    EXPECT_EQ(exit_code_for(ErrorCode::Internal), 1);
}

// A lost device and a failed allocation have their own codes, told by the error's VkResult.
TEST(CliExitCodes, DeviceLostAndOutOfMemoryByTheirVkResult) {
    using fdmsurf::Error;
    using fdmsurf::cli::exit_code_for;
    EXPECT_EQ(exit_code_for(Error(ErrorCode::Vulkan, "lost", VK_ERROR_DEVICE_LOST)), 6);
    EXPECT_EQ(exit_code_for(Error(ErrorCode::Vulkan, "oom", VK_ERROR_OUT_OF_DEVICE_MEMORY)), 7);
    EXPECT_EQ(exit_code_for(Error(ErrorCode::DeviceLimit, "oom", VK_ERROR_OUT_OF_HOST_MEMORY)), 7);
    EXPECT_EQ(exit_code_for(Error(ErrorCode::DeviceLimit, "too wide")), 4);
    EXPECT_EQ(exit_code_for(Error(ErrorCode::Vulkan, "other", VK_ERROR_INITIALIZATION_FAILED)), 4);
    // A VkFFTResult is not a VkResult: its numbers mean something else.
    EXPECT_EQ(exit_code_for(Error(ErrorCode::Fft, "fft", VK_ERROR_DEVICE_LOST)), 4);
    EXPECT_EQ(exit_code_for(Error(ErrorCode::Format, "bad")), 3);
}

TEST(CliOptions, SurfaceNamesRoundTrip) {
    for (SurfaceKind kind : {SurfaceKind::Ses, SurfaceKind::Vdw, SurfaceKind::Sas}) {
        const std::string name = fdmsurf::cli::surface_name(kind);
        EXPECT_EQ(parse_with({"--surface", name}).surface.surface, kind) << name;
    }
}

}  // namespace

namespace {

using fdmsurf::SesMethod;

TEST(CliOptions, SesMethods) {
    EXPECT_EQ(parse_with({}).surface.method, SesMethod::Fdm);
    EXPECT_EQ(parse_with({"--method", "edt"}).surface.method, SesMethod::Edt);
    EXPECT_EQ(parse_with({"--method=fdm"}).surface.method, SesMethod::Fdm);
    // The exact SES keeps every cavity unless told otherwise.
    EXPECT_LT(parse_with({"--method", "edt"}).surface.min_cavity_volume, 0.0f);
    EXPECT_TRUE(contains(parse_error_with({"--method", "msms"}), "fdm or edt"));
}

TEST(CliOptions, EdtRefusesWhatOnlyTheFdmMethodHas) {
    EXPECT_TRUE(
        contains(parse_error_with({"--method", "edt", "--surface", "vdw"}), "--surface vdw"));
    EXPECT_TRUE(contains(parse_error_with({"--method", "edt", "--paper"}), "--paper"));
    for (const char* option : {"--cutoff", "--sigma", "--level"})
        EXPECT_TRUE(contains(parse_error_with({"--method", "edt", option, "0.5"}), option))
            << option;
    EXPECT_TRUE(contains(parse_error_with({"--filter", "ideal", "--method", "edt"}), "--filter"));
    // What both methods share is accepted.
    const CliOptions o = parse_with({"--method", "edt", "--probe", "1.2", "--spacing", "0.4",
                                     "--refine", "1", "--no-cavities"});
    EXPECT_EQ(o.surface.probe, 1.2f);
    EXPECT_EQ(o.surface.refine, 1);
}

}  // namespace
