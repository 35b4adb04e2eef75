// `--save-map PREFIX` (the map files of freespace/map_io.hpp) and `--polygon-format` from the
// command line.
#include "output_options.hpp"

#include <filesystem>
#include <iostream>

#include "engine_options.hpp"
#include "freespace/errors.hpp"
#include "freespace/map_io.hpp"
#include "output/polygon_text.hpp"
#include "output/report.hpp"

namespace freespace::cli {

void AddSaveMapOption(CLI::App* command, std::string* prefix) {
  command
      ->add_option("--save-map", *prefix,
                   "After the last scan, write the local map as PREFIX.pgm + PREFIX.yaml (a\n"
                   "map_server map: trinary, occupied p > 0.65, free p < 0.196) and its raw\n"
                   "log-odds as PREFIX.npy (int16, row 0 south); see docs/formats.md")
      ->check(CLI::Validator(
          [](std::string& prefix) -> std::string {
            if (prefix.empty() || prefix.back() == '/') {
              return "'" + prefix + "' names no file (a folder's map: FOLDER/map)";
            }
            return "";
          },
          ""));
}

void AddMapOutputs(const std::string& prefix, std::vector<NamedPath>* outputs) {
  if (prefix.empty()) return;
  const MapFiles files = MapFilesAt(prefix);
  for (const std::string& path : {files.pgm, files.yaml, files.npy})
    outputs->push_back({"--save-map", path});
}

void RefuseOverwritingInputs(const std::vector<NamedPath>& inputs,
                             const std::vector<NamedPath>& outputs) {
  for (const NamedPath& out : outputs) {
    for (const NamedPath& in : inputs) {
      std::error_code error;  // either missing: not the same file
      if (out.path.empty() || in.path.empty() ||
          !std::filesystem::equivalent(out.path, in.path, error) || error) {
        continue;
      }
      throw InputError(out.option + " would write " + out.path + ", the file " + in.option +
                       " reads (" + in.path + "); give another path");
    }
  }
}

void SaveMapIfAsked(const std::string& prefix, const MapView& map, const std::string& command) {
  if (prefix.empty()) return;
  const std::filesystem::path parent = std::filesystem::path(prefix).parent_path();
  if (!parent.empty()) MakeDirectories(parent.string());
  const MapFiles files = SaveMap(map, prefix);
  std::cerr << "freespace " << command << ": wrote the map " << map.width << " x " << map.height
            << " at " << map.resolution_m << " m to " << files.yaml << ", " << files.pgm << " and "
            << files.npy << "\n";
}

void AddPolygonFormatOption(CLI::App* command, std::string* format) {
  command
      ->add_option("--polygon-format", *format,
                   "jsonl: OUT/polygons.jsonl; geojson: OUT/polygons.geojsonl instead, one\n"
                   "GeoJSON Feature (RFC 7946 Polygon, world-frame metres) per scan a line")
      ->check(CLI::IsMember({"jsonl", "geojson"}))
      ->capture_default_str();
}

std::string PolygonFileName(const std::string& format) {
  return format == "geojson" ? "polygons.geojsonl" : "polygons.jsonl";
}

std::string PolygonLine(const std::string& format, const Result& r) {
  return format == "geojson" ? PolygonGeoJsonLine(r) : PolygonJsonLine(r.scan_index, r);
}

}  // namespace freespace::cli
