// Van der Waals radii by element: Bondi (1964) first, gemmi's table for the elements Bondi lacks.
// A. Bondi, "van der Waals Volumes and Radii", J. Phys. Chem. 68 (1964) 441-451.
#include <cctype>
#include <gemmi/elem.hpp>

#include "structure/detail.hpp"

namespace fdmsurf {

namespace {

struct Radius {
    const char* symbol;  // upper case, as gemmi's element_uppercase_name
    float radius;        // Å
};

// Bondi's table 1964. Deuterium is given hydrogen's radius.
constexpr Radius kBondi[] = {
    {"H", 1.20f},  {"D", 1.20f},  {"HE", 1.40f}, {"C", 1.70f},  {"N", 1.55f},  {"O", 1.52f},
    {"F", 1.47f},  {"NE", 1.54f}, {"SI", 2.10f}, {"P", 1.80f},  {"S", 1.80f},  {"CL", 1.75f},
    {"AR", 1.88f}, {"AS", 1.85f}, {"SE", 1.90f}, {"BR", 1.85f}, {"KR", 2.02f}, {"TE", 2.06f},
    {"I", 1.98f},  {"XE", 2.16f}, {"LI", 1.82f}, {"NA", 2.27f}, {"MG", 1.73f}, {"K", 2.75f},
    {"NI", 1.63f}, {"CU", 1.40f}, {"ZN", 1.39f}, {"GA", 1.87f}, {"PD", 1.63f}, {"AG", 1.72f},
    {"CD", 1.58f}, {"IN", 1.93f}, {"SN", 2.17f}, {"PT", 1.72f}, {"AU", 1.66f}, {"HG", 1.55f},
    {"TL", 1.96f}, {"PB", 2.02f}, {"U", 1.86f},
};

gemmi::El find_known(std::string_view symbol) {
    symbol = detail::trim(symbol);
    // gemmi's find_element reads two characters at most; longer strings are no symbol.
    if (symbol.empty() || symbol.size() > 2) return gemmi::El::X;
    for (char c : symbol)
        if (!std::isalpha(static_cast<unsigned char>(c))) return gemmi::El::X;
    char buf[3] = {symbol[0], symbol.size() > 1 ? symbol[1] : '\0', '\0'};
    return gemmi::find_element(buf);
}

}  // namespace

float vdw_radius(std::string_view element) {
    gemmi::El el = find_known(element);
    if (el == gemmi::El::X) return -1.0f;
    std::string_view upper = gemmi::element_uppercase_name(el);
    for (const Radius& r : kBondi)
        if (upper == r.symbol) return r.radius;
    float r = gemmi::vdw_radius(el);
    return r > 0.0f ? r : -1.0f;
}

namespace detail {

std::string known_element(std::string_view symbol) {
    gemmi::El el = find_known(symbol);
    return el == gemmi::El::X ? std::string() : std::string(gemmi::element_uppercase_name(el));
}

}  // namespace detail

}  // namespace fdmsurf
