// `fdmsurf prepare [--device D] [--validation] [--quiet]`.
#include "cli/prepare_command.hpp"

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "cli/messages.hpp"
#include "cli/options.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/surface.hpp"
#include "engine/engine_impl.hpp"
#include "filter/plan_cache.hpp"

namespace fdmsurf::cli {

std::string prepare_usage_text() {
    return R"(usage: fdmsurf prepare [--device D] [--validation] [--quiet]

Builds, once per machine, what the first surface of a small structure would otherwise spend
seconds on: the FFT plans of the grid sizes to which fdmsurf rounds small grids (cubes of 64,
80, 96, 112, 128, 144 and 160 points; see --natural-grid), kept in fdmsurf's plan cache
($FDMSURF_CACHE_DIR, else $XDG_CACHE_HOME/fdmsurf, else ~/.cache/fdmsurf), and the driver's
compiled kernels of the default fdm, edt, vdw and sas surfaces, kept in the driver's own shader
cache (Mesa: ~/.cache/mesa_shader_cache). Both caches belong to the user who runs it.
scripts/setup-debian.sh runs it after the build. Running it again costs little: the plans are
then read from the cache.

  --device D     the device to prepare for (index or part of its name; default: the one a run
                 uses); plans and compiled kernels are per device and driver
  --validation   enable the Khronos validation layer; its messages are errors
  --quiet        print nothing but errors
  --help         this text
)";
}

int prepare_command(const std::vector<std::string>& args) {
    return report_errors([&] {
        EngineOptions engine;
        bool quiet = false;
        for (std::size_t i = 0; i < args.size(); ++i) {
            const std::string& a = args[i];
            if (a == "--help" || a == "-h") {
                std::fputs(prepare_usage_text().c_str(), stdout);
                return kExitOk;
            }
            if (a == "--quiet" || a == "-q") {
                quiet = true;
            } else if (a == "--validation") {
                engine.validation = true;
            } else if (a == "--device" || a.rfind("--device=", 0) == 0) {
                const bool joined = a != "--device";
                const std::string value =
                    joined ? a.substr(9) : (i + 1 < args.size() ? args[i + 1] : std::string());
                if (value.empty() || (!joined && value.front() == '-'))
                    throw Error(ErrorCode::InvalidArgument,
                                "prepare: option --device needs a value, a device's index or "
                                "part of its name (see fdmsurf prepare --help)");
                if (!joined) ++i;
                engine.device = value;
            } else {
                throw Error(ErrorCode::InvalidArgument, "prepare: unknown argument '" + a +
                                                            "' (see fdmsurf prepare --help)");
            }
        }
        const auto start = std::chrono::steady_clock::now();
        Engine e(engine);
        e.impl().make_pipelines();  // made at first use otherwise
        const double init_ms = std::chrono::duration<double, std::milli>(
                                   std::chrono::steady_clock::now() - start)
                                   .count();
        const std::vector<Engine::PreparedPlan> plans = e.prepare();
        const std::vector<std::string> messages = e.take_validation_messages();
        for (const std::string& m : messages) print_error("validation: " + m);
        if (!messages.empty()) return kExitValidation;
        const std::string cache = detail::PlanCache::default_directory();
        bool unwritable = false;
        for (const Engine::PreparedPlan& p : plans) unwritable |= !p.from_cache && !p.stored;
        unwritable &= !cache.empty();
        if (unwritable)
            print_warning("the plan cache " + cache +
                          " cannot be written (a file in the way, or no permission): every run "
                          "builds its FFT plans again; set FDMSURF_CACHE_DIR to a folder that "
                          "can be written");
        if (quiet) return kExitOk;
        std::printf("device    %s (%s)\n", e.device().name.c_str(), e.device().driver.c_str());
        std::printf("pipelines %.0f ms (the engine's own kernels)\n", init_ms);
        for (const Engine::PreparedPlan& p : plans) {
            char size[48];
            std::snprintf(size, sizeof size, "%ux%ux%u", p.dims[0], p.dims[1], p.dims[2]);
            std::printf("FFT %-11s  %6.0f ms  %s\n", size, p.ms,
                        p.from_cache   ? "plan read from the plan cache"
                        : cache.empty() ? "plan built (plan cache off: FDMSURF_CACHE_DIR=off)"
                        : p.stored      ? "plan built and cached"
                                        : "plan built, not cached (the cache cannot be written)");
        }
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                           start)
                                 .count();
        std::printf("prepared in %.1f s (with the exact SES, vdw and sas kernels)\n", total);
        return kExitOk;
    });
}

}  // namespace fdmsurf::cli
