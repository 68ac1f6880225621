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

namespace fdmsurf::cli {

std::string prepare_usage_text() {
    return R"(usage: fdmsurf prepare [--device D] [--validation] [--quiet]

Builds, once per machine, what the first surface of a small structure would otherwise spend
seconds on: the FFT plans of the grid sizes to which fdmsurf rounds small grids (cubes of 64,
80, 96, 112, 128, 144 and 160 points; see --natural-grid), kept in fdmsurf's plan cache
($FDMSURF_CACHE_DIR, else ~/.cache/fdmsurf), and the driver's compiled kernels, kept in the
driver's own shader cache (Mesa: ~/.cache/mesa_shader_cache). scripts/setup-debian.sh runs it
after the build. Running it again costs little: the plans are then read from the cache.

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
                if (a == "--device") {
                    if (i + 1 >= args.size())
                        throw Error(ErrorCode::InvalidArgument,
                                    "prepare: option --device needs a value (see fdmsurf "
                                    "prepare --help)");
                    engine.device = args[++i];
                } else {
                    engine.device = a.substr(9);
                }
            } else {
                throw Error(ErrorCode::InvalidArgument, "prepare: unknown argument '" + a +
                                                            "' (see fdmsurf prepare --help)");
            }
        }
        const auto start = std::chrono::steady_clock::now();
        Engine e(engine);
        const double init_ms = std::chrono::duration<double, std::milli>(
                                   std::chrono::steady_clock::now() - start)
                                   .count();
        const std::vector<Engine::PreparedPlan> plans = e.prepare();
        const std::vector<std::string> messages = e.take_validation_messages();
        for (const std::string& m : messages) print_error("validation: " + m);
        if (!messages.empty()) return kExitFailure;
        if (quiet) return kExitOk;
        std::printf("device    %s (%s)\n", e.device().name.c_str(), e.device().driver.c_str());
        std::printf("pipelines %.0f ms (the engine's own kernels)\n", init_ms);
        for (const Engine::PreparedPlan& p : plans) {
            std::printf("FFT %ux%ux%u  %6.0f ms  %s\n", p.dims[0], p.dims[1], p.dims[2], p.ms,
                        p.from_cache ? "plan read from the plan cache"
                                     : "plan built and cached");
        }
        const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() -
                                                           start)
                                 .count();
        std::printf("prepared in %.1f s (with the exact SES, vdw and sas kernels)\n", total);
        return kExitOk;
    });
}

}  // namespace fdmsurf::cli
