// --models all with --areas FILE: one table of every model (CSV or JSON Lines), a row each with
// the model's surface (area, volume, pieces, cavities) and its exact SASA in total and by chain,
// so that an NMR ensemble or a multi-model PDB from an MD program is a time series.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"

namespace fdmsurf::cli {

// One model's row. The surface's fields are those of its mesh (has_mesh false without -o, or
// when the mesh stayed on the device for a picture); the SASA is the exact sphere patches of
// radius r + probe (atom_exact_areas), whatever the surface kind.
struct ModelRow {
    int model = 0;
    bool ok = true;
    std::string error;  // why the model failed (ok false)
    std::size_t atoms = 0;
    bool has_mesh = false;
    double area = 0.0;           // Å²
    double volume = 0.0;         // Å³, signed (cavities count negative)
    std::size_t pieces = 0;      // connected pieces of the mesh
    std::size_t cavities = 0;    // pieces of negative volume
    double cavity_volume = 0.0;  // Å³, their volume, positive
    double sasa = 0.0;           // Å², exact
    std::vector<std::pair<std::string, double>> chain_sasa;  // Å² per chain, in atom order
};

// True for a --areas path that holds the model table (.csv or .jsonl, any case) when given
// with --models all; .jsonl is the table's alone.
bool is_jsonl_path(const std::string& path);

// The row's SASA (total and per chain) for `structure`'s atoms at `probe` Å.
void add_sasa(ModelRow& row, const Structure& structure, float probe);

// The mesh's fields of the row: area, volume, pieces and cavities.
void add_mesh(ModelRow& row, const Mesh& mesh, const MeshStats& stats);

// The row as one JSON object (a line of the .jsonl table): model, status, error (failed rows),
// atoms, area, volume, pieces, cavities, cavity_volume (null without a mesh), sasa, chain_sasa.
std::string model_row_json(const ModelRow& row);

// Writes the rows as CSV (header: model, status, error, atoms, area, volume, pieces, cavities,
// cavity_volume, sasa, then sasa_CHAIN for every chain of any row, in order of first
// appearance) or JSON Lines (one object per row, chain_sasa as an object) by the extension of
// `path`, through a temporary file renamed into place: the table is whole or absent.
void write_models_table(const std::vector<ModelRow>& rows, const std::string& path);

}  // namespace fdmsurf::cli
