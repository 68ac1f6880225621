// libFuzzer harness for MSMS's .vert/.face pair as `fdmsurf compare` reads it: the input is
// the .vert text, a NUL byte, then the .face text (no NUL: an empty .face).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_common.hpp"
#include "mesh/compare_detail.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fdmsurf;
    const std::string_view text = fuzz::as_text(data, size);
    const std::size_t split = text.find('\0');
    const std::string_view vert = text.substr(0, split);
    const std::string_view face =
        split == std::string_view::npos ? std::string_view() : text.substr(split + 1);
    fuzz::expect_success_or_error([&] {
        fuzz::check_mesh(detail::parse_msms(vert, "fuzz.vert", face, "fuzz.face"));
    });
    return 0;
}
