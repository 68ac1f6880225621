// Structure input entry points: load, check, pick the format, hand over to that format's reader.
#include "fdmsurf/structure.hpp"

#include <istream>
#include <string_view>
#include <utility>
#include <vector>

#include "structure/detail.hpp"

namespace fdmsurf {

namespace {

// Every model (options.model == kAllModels) or the one asked for.
std::vector<Structure> read_text(std::string_view text, const std::string& name,
                                 const ReadOptions& options) {
    // A UTF-8 byte-order mark (editors on Windows write one) is not part of any record: gemmi
    // would refuse an mmCIF that starts with it ("expected block header").
    if (text.substr(0, 3) == "\xEF\xBB\xBF")
        return read_text(text.substr(3), name, options);
    detail::check_text(text, name);
    if (options.model < 0)
        throw Error(ErrorCode::InvalidArgument, name + ": model " + std::to_string(options.model) +
                                                    " requested (models are numbered from 1)");
    if (options.assembly < 0)
        throw Error(ErrorCode::InvalidArgument,
                    name + ": assembly " + std::to_string(options.assembly) +
                        " requested (assemblies are numbered from 1; 0 is the model as "
                        "deposited)");
    // Bad selection syntax is reported before the file is parsed.
    if (!options.select.empty()) detail::Selection check(options.select, name);
    StructureFormat format = options.format == StructureFormat::Auto
                                 ? detail::detect_format(text, name)
                                 : options.format;
    if (format == StructureFormat::Pdb || format == StructureFormat::Mmcif)
        return detail::read_pdb_or_mmcif(text, name, format, options);
    // PQR, XYZR and XYZRN hold one model and no assemblies; asking for more is a mistake worth
    // reporting.
    if (options.model > 1)
        throw Error(ErrorCode::InvalidArgument, name + ": model " + std::to_string(options.model) +
                                                    " requested, but " + to_string(format) +
                                                    " input has one model");
    if (options.assembly != 0)
        throw Error(ErrorCode::InvalidArgument,
                    name + ": assembly " + std::to_string(options.assembly) + " requested, but " +
                        to_string(format) + " input has no assemblies (PDB and mmCIF only)");
    std::vector<Structure> out;
    out.push_back(format == StructureFormat::Pqr     ? detail::read_pqr(text, name)
                  : format == StructureFormat::Xyzrn ? detail::read_xyzrn(text, name)
                                                     : detail::read_xyzr(text, name));
    detail::filter_read_atoms(out.front(), options, name);
    return out;
}

Structure one_model(std::string_view text, const std::string& name, const ReadOptions& options) {
    if (options.model == kAllModels)
        throw Error(ErrorCode::InvalidArgument,
                    name +
                        ": model 0 requested (models are numbered from 1; every model at "
                        "once needs read_models)");
    std::vector<Structure> models = read_text(text, name, options);
    return std::move(models.front());
}

// All of a stream's bytes, decompressed when gzip data.
std::string load_stream(std::istream& in, const std::string& name) {
    std::string bytes;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0)
        bytes.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (in.bad()) throw Error(ErrorCode::Io, name + ": read error");
    return detail::decompress(std::move(bytes), name);
}

}  // namespace

Structure read_structure(const std::string& path, const ReadOptions& options) {
    const detail::FileText file(path);
    return one_model(file.text(), path, options);
}

Structure read_structure_from_memory(std::string_view data, const std::string& name,
                                     const ReadOptions& options) {
    return one_model(data, name, options);
}

std::vector<Structure> read_models(const std::string& path, const ReadOptions& options) {
    const detail::FileText file(path);
    return read_text(file.text(), path, options);
}

Structure read_structure(std::istream& in, const std::string& name, const ReadOptions& options) {
    return one_model(load_stream(in, name), name, options);
}

std::vector<Structure> read_models(std::istream& in, const std::string& name,
                                   const ReadOptions& options) {
    return read_text(load_stream(in, name), name, options);
}

std::vector<Structure> read_models_from_memory(std::string_view data, const std::string& name,
                                               const ReadOptions& options) {
    return read_text(data, name, options);
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
        case StructureFormat::Xyzrn:
            return "xyzrn";
    }
    return "unknown";
}

}  // namespace fdmsurf
