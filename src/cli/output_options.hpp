// Output options of the commands that run the estimator: `--save-map PREFIX` (run, demo), the
// map after the last scan as a map_server map (PREFIX.pgm + PREFIX.yaml) and raw log-odds
// (PREFIX.npy); `--polygon-format jsonl|geojson` (run), the file the polygons go to.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "freespace/result.hpp"

namespace freespace::cli {

void AddSaveMapOption(CLI::App* command, std::string* prefix);

// A file a command reads or writes, and the option that names it.
struct NamedPath {
  std::string option, path;
};
// Adds the files `--save-map prefix` writes (none when `prefix` is empty).
void AddMapOutputs(const std::string& prefix, std::vector<NamedPath>* outputs);
// Throws InputError, before anything is written, when an output is the file an input names
// (through another path or a link too): the input would be overwritten while or after it is
// read.
void RefuseOverwritingInputs(const std::vector<NamedPath>& inputs,
                             const std::vector<NamedPath>& outputs);

// Writes the map's files at `prefix`, creating its folder, and says on stderr what it wrote;
// does nothing when `prefix` is empty. Throws InputError when a file cannot be written.
void SaveMapIfAsked(const std::string& prefix, const MapView& map, const std::string& command);

// --polygon-format: "jsonl" (polygons.jsonl, the default) or "geojson" (polygons.geojsonl, one
// GeoJSON Feature a line).
void AddPolygonFormatOption(CLI::App* command, std::string* format);
std::string PolygonFileName(const std::string& format);
// The line (without newline) of scan `r` in the file of `format`.
std::string PolygonLine(const std::string& format, const Result& r);

}  // namespace freespace::cli
