// libFuzzer harness for the command-line parsers: the input's first byte picks the parser
// (fdmsurf's own options, `fdmsurf msms`'s MSMS options, `fdmsurf compare`'s), the rest is the
// argument list, one argument per NUL-separated field. Bad arguments must be Error naming
// them; nothing else may escape, and what parses must be usable (output names formed).
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "cli/compare_command.hpp"
#include "cli/msms_command.hpp"
#include "cli/options.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fdmsurf;
    if (size == 0) return 0;
    const int parser = data[0] % 3;
    std::vector<std::string> args;
    std::string_view rest = fuzz::as_text(data + 1, size - 1);
    while (!rest.empty()) {
        const std::size_t end = rest.find('\0');
        args.emplace_back(rest.substr(0, end));
        rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    }
    fuzz::expect_success_or_error([&] {
        if (parser == 0) {
            const cli::CliOptions options = cli::parse_args(args);
            if (!options.output.empty()) {
                for (const std::string& input : options.inputs) {
                    FDMSURF_FUZZ_CHECK(!cli::primary_output(options, input, 1).empty());
                }
            }
        } else if (parser == 1) {
            const cli::MsmsOptions options = cli::parse_msms_args(args);
            if (!options.help && options.spacing <= 0.0f) {
                const float spacing = cli::spacing_for_density(options.density);
                FDMSURF_FUZZ_CHECK(spacing > 0.0f);
            }
        } else {
            (void)cli::parse_compare_args(args);
        }
    });
    return 0;
}
