// The table of every model for --models all --areas FILE (models_table.hpp; docs/cli.md).
#include "cli/models_table.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "base/text.hpp"
#include "cli/json.hpp"
#include "io/atomic_file.hpp"

namespace fdmsurf::cli {

namespace {

using detail::csv_field;

bool ends_with_lower(const std::string& path, const std::string& suffix) {
    if (path.size() < suffix.size()) return false;
    std::string tail = path.substr(path.size() - suffix.size());
    for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return tail == suffix;
}

std::string number(double value) {
    return json_number(value) == "null" ? std::string() : json_number(value);
}

std::vector<std::string> all_chains(const std::vector<ModelRow>& rows) {
    std::vector<std::string> chains;
    for (const ModelRow& row : rows)
        for (const auto& [chain, area] : row.chain_sasa)
            if (std::find(chains.begin(), chains.end(), chain) == chains.end())
                chains.push_back(chain);
    return chains;
}

void write_csv(const std::vector<ModelRow>& rows, detail::AtomicFile& out) {
    const std::vector<std::string> chains = all_chains(rows);
    std::string line =
        "model,status,error,atoms,area,volume,pieces,cavities,cavity_volume,sasa";
    for (const std::string& chain : chains) line += "," + csv_field("sasa_" + chain);
    out.write(line + "\n");
    for (const ModelRow& r : rows) {
        line = std::to_string(r.model) + "," + (r.ok ? "ok" : "failed") + "," +
               csv_field(r.error) + ",";
        if (!r.ok) {
            line += std::string(7 + chains.size(), ',');
            out.write(line + "\n");
            continue;
        }
        line += std::to_string(r.atoms) + ",";
        if (r.has_mesh)
            line += number(r.area) + "," + number(r.volume) + "," + std::to_string(r.pieces) +
                    "," + std::to_string(r.cavities) + "," + number(r.cavity_volume) + ",";
        else
            line += ",,,,,";
        line += number(r.sasa);
        for (const std::string& chain : chains) {
            line += ",";
            for (const auto& [c, area] : r.chain_sasa)
                if (c == chain) line += number(area);
        }
        out.write(line + "\n");
    }
}

}  // namespace

std::string model_row_json(const ModelRow& r) {
    JsonWriter w;
    w.begin_object();
    w.member("model", r.model);
    w.member("status", r.ok ? "ok" : "failed");
    if (!r.ok) {
        w.member("error", r.error);
    } else {
        w.member("atoms", r.atoms);
        auto mesh_number = [&](const char* key, double value) {
            if (r.has_mesh)
                w.member(key, value);
            else
                w.member(key, nullptr);
        };
        mesh_number("area", r.area);
        mesh_number("volume", r.volume);
        if (r.has_mesh) {
            w.member("pieces", r.pieces);
            w.member("cavities", r.cavities);
        } else {
            w.member("pieces", nullptr);
            w.member("cavities", nullptr);
        }
        mesh_number("cavity_volume", r.cavity_volume);
        w.member("sasa", r.sasa);
        w.key("chain_sasa").begin_object();
        for (const auto& [chain, area] : r.chain_sasa) w.member(chain, area);
        w.end_object();
    }
    w.end_object();
    return w.str();
}

bool is_jsonl_path(const std::string& path) { return ends_with_lower(path, ".jsonl"); }

void add_sasa(ModelRow& row, const Structure& structure, float probe) {
    const Atoms& atoms = structure.atoms;
    const std::vector<double> areas = atom_exact_areas(atoms, probe);
    row.atoms = atoms.size();
    row.sasa = 0.0;
    for (double a : areas) row.sasa += a;
    if (atoms.meta.size() != atoms.size()) return;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const std::string& chain = atoms.meta[i].chain;
        auto it = std::find_if(row.chain_sasa.begin(), row.chain_sasa.end(),
                               [&](const auto& entry) { return entry.first == chain; });
        if (it == row.chain_sasa.end())
            row.chain_sasa.emplace_back(chain, areas[i]);
        else
            it->second += areas[i];
    }
}

void add_mesh(ModelRow& row, const Mesh& mesh, const MeshStats& stats) {
    row.has_mesh = true;
    row.area = stats.area;
    row.volume = stats.volume;
    row.pieces = stats.pieces;
    row.cavities = 0;
    row.cavity_volume = 0.0;
    for (const MeshStats& piece : piece_stats(mesh))
        if (piece.volume < 0.0) {
            ++row.cavities;
            row.cavity_volume -= piece.volume;
        }
}

void write_models_table(const std::vector<ModelRow>& rows, const std::string& path) {
    detail::AtomicFile out(path);
    if (is_jsonl_path(path))
        for (const ModelRow& r : rows) out.write(model_row_json(r) + "\n");
    else
        write_csv(rows, out);
    out.commit();
}

}  // namespace fdmsurf::cli
