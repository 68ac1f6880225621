// `fdmsurf msms` (and the program started as `msms`): MSMS's command line and files.
#pragma once

#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"

namespace fdmsurf::cli {

// What an MSMS command line asks for, in fdmsurf's terms (docs/formats.md has the mapping).
struct MsmsOptions {
    std::string input;          // -if
    std::string output_base;    // -of (empty: no surface files)
    std::string area_base;      // -af (empty: no area file)
    float probe = 1.5f;         // -probe_radius, MSMS's default
    float density = 1.0f;       // -density, vertices per Å² (MSMS's default)
    float hdensity = 3.0f;      // -hdensity (MSMS's default)
    bool density_given = false;
    bool hdensity_given = false;
    bool header = true;         // -no_header
    bool areas = true;          // -no_area
    bool triangulate = true;    // -surface tses|ses (true) or ases (false)
    bool all_components = false;
    float spacing = 0.0f;       // -spacing (fdmsurf): overrides the density; 0: from it
    SesMethod method = SesMethod::Edt;  // -method (fdmsurf): edt, MSMS's exact SES, or fdm
    std::string device;         // -device (fdmsurf)
    bool validation = false;    // -validation (fdmsurf)
    // -host_filter, -host_density, -host_mc, -host_atoms, -host_ses (fdmsurf): where those
    // stages run, as the main command's --host-* options (EngineOptions).
    StagePlace gaussian_filter = StagePlace::Auto;
    StagePlace density_place = StagePlace::Auto;
    StagePlace marching_cubes = StagePlace::Auto;
    StagePlace vertex_atoms = StagePlace::Auto;
    StagePlace ses_distance = StagePlace::Auto;
    bool help = false;
    std::vector<std::string> warnings;  // options accepted and ignored
};

// Parses MSMS's options as MSMS does: any order, each option's name may be abbreviated (the
// first option, in MSMS's order, whose name starts with the abbreviation). Throws
// Error(InvalidArgument) naming the option for a missing or bad value or an unknown option.
MsmsOptions parse_msms_args(const std::vector<std::string>& args);

// The grid spacing (Å) that gives at least `density` vertices per Å² (docs/formats.md).
float spacing_for_density(float density);

std::string msms_usage_text();

// Runs it; returns the process exit code. Errors are printed.
int msms_command(const std::vector<std::string>& args);

}  // namespace fdmsurf::cli
