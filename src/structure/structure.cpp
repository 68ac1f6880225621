// Structure input entry points: load, check, pick the format, hand over to that format's reader.
#include "fdmsurf/structure.hpp"

#include "structure/detail.hpp"

namespace fdmsurf {

namespace {

Structure read_text(const std::string& text, const std::string& name, const ReadOptions& options) {
    detail::check_text(text, name);
    if (options.model < 1)
        throw Error(ErrorCode::InvalidArgument, name + ": model " + std::to_string(options.model) +
                                                    " requested (models are numbered from 1)");
    StructureFormat format = options.format == StructureFormat::Auto
                                 ? detail::detect_format(text, name)
                                 : options.format;
    if (format == StructureFormat::Pdb || format == StructureFormat::Mmcif)
        return detail::read_pdb_or_mmcif(text, name, format, options);
    // PQR and XYZR hold one model; asking for another is a mistake worth reporting.
    if (options.model != 1)
        throw Error(ErrorCode::InvalidArgument, name + ": model " + std::to_string(options.model) +
                                                    " requested, but " + to_string(format) +
                                                    " input has one model");
    return format == StructureFormat::Pqr ? detail::read_pqr(text, name)
                                          : detail::read_xyzr(text, name);
}

}  // namespace

Structure read_structure(const std::string& path, const ReadOptions& options) {
    return read_text(detail::load_file(path), path, options);
}

Structure read_structure_from_memory(std::string_view data, const std::string& name,
                                     const ReadOptions& options) {
    return read_text(std::string(data), name, options);
}

const char* to_string(StructureFormat format) noexcept {
    switch (format) {
        case StructureFormat::Auto:
            return "auto";
        case StructureFormat::Pdb:
            return "pdb";
        case StructureFormat::Mmcif:
            return "mmcif";
        case StructureFormat::Pqr:
            return "pqr";
        case StructureFormat::Xyzr:
            return "xyzr";
    }
    return "unknown";
}

}  // namespace fdmsurf
