// Config: defaults, YAML round trip, error messages that name the field and the value, and the
// project's files that must follow the field table: docs/configuration.md and configs/*.yaml.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "core/config_fields.hpp"
#include "test_util.hpp"

namespace freespace {
namespace {

std::string ErrorOf(const std::string& yaml) {
  try {
    Config::FromYaml(yaml, "test.yaml").Validate();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(Config, DefaultsAreThePapersAndValid) {
  const Config c;
  EXPECT_NO_THROW(c.Validate());
  EXPECT_EQ(c.map.width_cells, 300);
  EXPECT_EQ(c.map.height_cells, 300);
  EXPECT_DOUBLE_EQ(c.map.resolution_m, 0.2);
  EXPECT_DOUBLE_EQ(c.sensor_model.p_free, 0.40);
  EXPECT_DOUBLE_EQ(c.sensor_model.p_occupied, 0.65);
  EXPECT_EQ(c.clutter.min_cluster_size, 5);
  EXPECT_EQ(c.sensor.layers, 4);
  EXPECT_DOUBLE_EQ(c.sensor.max_angle_deg - c.sensor.min_angle_deg, 145.0);
}

TEST(Config, YamlRoundTripKeepsEveryField) {
  Config c;
  c.map.width_cells = 1500;
  c.sensor.mount_x_m = 3.7;
  c.clutter.enabled = false;
  c.sensor_model.kind = SensorModelKind::kConventional;
  c.alignment.kind = AlignmentKind::kRotate;
  c.backend.kind = BackendKind::kAuto;
  c.backend.opencl_device = "pthread";
  c.backend.opencl_wait = OpenClWait::kSpin;
  c.backend.opencl_spin_us = 1234;
  c.backend.opencl_devices = 3;
  c.polygon.epsilon_m = 0.123456789;
  const Config back = Config::FromYaml(c.ToYaml());
  EXPECT_EQ(back.ToYaml(), c.ToYaml());
  EXPECT_EQ(back.map.width_cells, 1500);
  EXPECT_EQ(back.sensor_model.kind, SensorModelKind::kConventional);
  EXPECT_DOUBLE_EQ(back.polygon.epsilon_m, 0.123456789);
  EXPECT_EQ(back.backend.opencl_wait, OpenClWait::kSpin);
  EXPECT_EQ(back.backend.opencl_spin_us, 1234);
  EXPECT_EQ(back.backend.opencl_devices, 3);
}

TEST(Config, OpenClWaitNamesAndLimits) {
  EXPECT_EQ(Config().backend.opencl_wait, OpenClWait::kAuto);
  EXPECT_EQ(Config::FromYaml("backend:\n  opencl_wait: block\n").backend.opencl_wait,
            OpenClWait::kBlock);
  EXPECT_NE(ErrorOf("backend:\n  opencl_wait: sleep\n").find("backend.opencl_wait"),
            std::string::npos);
  EXPECT_NE(ErrorOf("backend:\n  opencl_spin_us: -1\n").find("backend.opencl_spin_us = -1"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("backend:\n  opencl_spin_us: 0\n"), "");
  EXPECT_EQ(Config().backend.opencl_devices, 1);
  EXPECT_EQ(Config::FromYaml("backend:\n  opencl_devices: 2\n").backend.opencl_devices, 2);
  EXPECT_NE(ErrorOf("backend:\n  opencl_devices: 0\n").find("backend.opencl_devices = 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf("backend:\n  opencl_devices: 17\n").find("backend.opencl_devices = 17"),
            std::string::npos);
}

// A directory is no config file (a stream opens it on Linux and reads nothing, which would be
// the empty config, every field a default); nor is a missing path.
TEST(Config, AFileThatIsADirectoryOrMissingIsAConfigError) {
  const std::string dir = ::testing::TempDir();
  try {
    Config::FromYamlFile(dir);
    ADD_FAILURE() << "a directory read as a config";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("is a directory"), std::string::npos) << e.what();
  }
  EXPECT_THROW(Config::FromYamlFile(dir + "/no-such-config.yaml"), ConfigError);
  // A read that fails (Linux's /proc/self/mem opens, and reading its first page gives EIO): an
  // error, not the text read so far taken as the config.
  try {
    Config::FromYamlFile("/proc/self/mem");
    ADD_FAILURE() << "a failed read made a config";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot"), std::string::npos) << e.what();
  }
}

TEST(Config, MissingFieldsKeepDefaults) {
  const Config c = Config::FromYaml("map:\n  resolution_m: 0.1\n");
  EXPECT_DOUBLE_EQ(c.map.resolution_m, 0.1);
  EXPECT_EQ(c.map.width_cells, 300);
  EXPECT_EQ(Config::FromYaml("").ToYaml(), Config().ToYaml());
}

TEST(Config, ErrorsNameTheFieldAndTheValue) {
  EXPECT_NE(ErrorOf("map:\n  resolution_m: -1\n").find("map.resolution_m = -1"), std::string::npos);
  EXPECT_NE(ErrorOf("map:\n  width_cells: abc\n").find("map.width_cells = 'abc'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("mapp:\n  width_cells: 3\n").find("unknown section 'mapp'"), std::string::npos);
  EXPECT_NE(ErrorOf("map:\n  widht_cells: 3\n").find("unknown field 'map.widht_cells'"),
            std::string::npos);
  EXPECT_NE(ErrorOf("backend:\n  kind: cuda\n").find("tbb | opencl | auto"), std::string::npos);
  EXPECT_NE(ErrorOf("classify:\n  t_high: 0.5\n").find("classify.t_high = 0.5"), std::string::npos);
  EXPECT_NE(ErrorOf("sensor_model:\n  p_free: 0.6\n").find("sensor_model.p_free = 0.6"),
            std::string::npos);
  EXPECT_NE(ErrorOf("polygon:\n  max_vertices: 2\n").find("polygon.max_vertices = 2"),
            std::string::npos);
  EXPECT_NE(ErrorOf("map: [1, 2\n").find("test.yaml:2: not valid YAML"), std::string::npos);
  EXPECT_NE(ErrorOf("alignment:\n  margin_m: 40\n").find("alignment.margin_m = 40"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sensor:\n  max_range_m: .nan\n").find("sensor.max_range_m = nan"),
            std::string::npos);
}

// What yaml-cpp alone would read silently otherwise: 010 as octal 8 and 0x40 as 64, an empty
// value as the text "null", and only the first of two documents.
TEST(Config, IntegersAreDecimalEmptyValuesAndSecondDocumentsAreErrors) {
  EXPECT_EQ(ErrorOf("polygon:\n  max_vertices: 010\n"),
            "test.yaml:2: polygon.max_vertices = '010': not a valid integer (decimal digits, no "
            "leading zero)");
  EXPECT_NE(ErrorOf("map:\n  width_cells: 0x40\n").find("not a valid integer (decimal"),
            std::string::npos);
  EXPECT_EQ(Config::FromYaml("map:\n  width_cells: 0\n").map.width_cells, 0);
  EXPECT_EQ(Config::FromYaml("map:\n  width_cells: +300\n").map.width_cells, 300);
  EXPECT_EQ(Config::FromYaml("map:\n  width_cells: '300'\n").map.width_cells, 300);
  EXPECT_DOUBLE_EQ(Config::FromYaml("map:\n  resolution_m: 010\n").map.resolution_m, 10.0);
  EXPECT_EQ(ErrorOf("backend:\n  opencl_device:\n"),
            "test.yaml:2: backend.opencl_device: no value (write '' for an empty string)");
  EXPECT_EQ(ErrorOf("map:\n  width_cells: ~\n"), "test.yaml:2: map.width_cells: no value");
  EXPECT_EQ(Config::FromYaml("backend:\n  opencl_device: ''\n").backend.opencl_device, "");
  EXPECT_EQ(ErrorOf("polygon:\n  max_vertices: 16\n---\nmap:\n  width_cells: 100\n"),
            "test.yaml:4: a second YAML document: a config is one document (merge the two)");
  EXPECT_NE(ErrorOf("polygon:\n  max_vertices: 16\n...\nmap:\n  width_cells: 100\n")
                .find("a second YAML document"),
            std::string::npos);
  // A stray marker with nothing after it is no second document; the config is the first.
  EXPECT_EQ(Config::FromYaml("polygon:\n  max_vertices: 16\n---\n").polygon.max_vertices, 16);
  EXPECT_EQ(Config::FromYaml("---\npolygon:\n  max_vertices: 16\n").polygon.max_vertices, 16);
  EXPECT_NE(ErrorOf("---\n---\npolygon:\n  max_vertices: 16\n").find("a second YAML document"),
            std::string::npos);
  // A text on which yaml-cpp's parser reports empty documents without end (YAML::LoadAll never
  // returned) is tests/fuzz/regressions/config/loadall-endless-documents.yaml.
  // The hint about bases only where a leading zero makes it one.
  EXPECT_EQ(ErrorOf("map:\n  width_cells: 100.0\n"),
            "test.yaml:2: map.width_cells = '100.0': not a valid integer");
}

// --set section.field=value: applied in order over a config, each checked as a config file's
// field is, the result validated; a rig's sensors are not set this way.
TEST(Config, SettingsChangeOneFieldEach) {
  Config road;
  road.polygon.shape = PolygonShape::kInside;
  const Config c = WithSettings(road, {"polygon.margin_cells=2", "alignment.scan_match=true",
                                       "polygon.margin_cells=1", "backend.opencl_device=''"});
  EXPECT_EQ(c.polygon.margin_cells, 1);
  EXPECT_TRUE(c.alignment.scan_match);
  EXPECT_EQ(c.polygon.shape, PolygonShape::kInside);
  EXPECT_EQ(c.backend.opencl_device, "");
  const auto error = [&](const Config& base, const std::string& setting) {
    try {
      WithSettings(base, {setting});
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error(road, "polygon.margin=1"),
            "--set polygon.margin=1: unknown field 'polygon.margin'");
  EXPECT_EQ(error(road, "polygon.max_vertices=010"),
            "--set polygon.max_vertices=010: polygon.max_vertices = '010': not a valid integer "
            "(decimal digits, no leading zero)");
  EXPECT_EQ(error(road, "margin_cells=1"),
            "--set margin_cells=1: expected section.field=value (e.g. polygon.margin_cells=0)");
  EXPECT_EQ(error(road, "polygon.margin_cells=[1]"),
            "--set polygon.margin_cells=[1]: the value must be one plain value ('' for an empty "
            "string)");
  EXPECT_EQ(error(Config(), "polygon.margin_cells=1"),
            "config: polygon.margin_cells = 1: needs polygon.shape inside (0 with the paper's "
            "polygon)");
  Config rig = road;
  rig.sensors = {SensorConfig{}, SensorConfig{}};
  rig.sensors[0].name = "a";
  rig.sensors[1].name = "b";
  EXPECT_NE(error(rig, "sensor.mount_x_m=1").find("the config is a rig"), std::string::npos);
  EXPECT_NE(error(rig, "sensors.name=c").find("a rig's sensors are set in the config file"),
            std::string::npos);
  EXPECT_EQ(WithSettings(rig, {"polygon.margin_cells=0"}).sensors.size(), 2u);
}

// Every malformed shape of YAML is a ConfigError naming the file, the line and the field (a
// YAML exception escaping would fail these tests), quoting a short printable excerpt.
TEST(Config, KeysThatAreNotPlainWordsAndRepeatedKeysAreConfigErrors) {
  EXPECT_EQ(ErrorOf("? [a, b]\n: 1\n"),
            "test.yaml:1: a section name must be a plain word, not '[a, b]'");
  EXPECT_EQ(ErrorOf("map:\n  ? {x: 1}\n  : 2\n"),
            "test.yaml:2: a field name must be a plain word, not '{x: 1}'");
  EXPECT_EQ(ErrorOf("map:\n  width_cells: 100\nsensor:\n  layers: 2\nmap:\n  height_cells: 50\n"),
            "test.yaml:5: section 'map' appears twice (first on line 1): merge the two");
  EXPECT_EQ(ErrorOf("map:\n  width_cells: 100\n  width_cells: 200\n"),
            "test.yaml:3: field 'map.width_cells' appears twice (first on line 2)");
  EXPECT_EQ(ErrorOf("map:\n  width_cells: [1, 2]\n"),
            "test.yaml:2: map.width_cells = '[1, 2]': not a valid integer");
  EXPECT_EQ(ErrorOf("backend:\n  kind: {a: b}\n"),
            "test.yaml:2: backend.kind = '{a: b}': must be one of tbb | opencl | auto");
  EXPECT_EQ(ErrorOf("map: 3\n"), "test.yaml:1: 'map' must be a mapping of fields");
  // yaml-cpp's own message can quote a raw byte of the input (found by tests/fuzz/fuzz_config).
  const std::string raw = ErrorOf(std::string("map:\n \0\xfa {x: 0}\n  : 2\n", 22));
  EXPECT_NE(raw.find("test.yaml:2: not valid YAML: "), std::string::npos) << raw;
  for (const char c : raw) EXPECT_TRUE(c >= 0x20 && c < 0x7f) << raw;
  // A value that contains itself through an alias is described, not printed forever.
  EXPECT_NE(ErrorOf("map:\n  width_cells: &a [*a]\n").find("test.yaml:2: map.width_cells = '"),
            std::string::npos);
  // A long or binary value is quoted as a bounded, printable excerpt.
  const std::string long_value = "map:\n  width_cells: " + std::string(100000, '9') + "x\n";
  const std::string error = ErrorOf(long_value);
  EXPECT_LT(error.size(), 200u) << error.substr(0, 300);
  EXPECT_NE(error.find("... (100001 bytes)"), std::string::npos) << error;
  const std::string binary = ErrorOf("map:\n  width_cells: \"\\x01\\x7f\"\n");
  EXPECT_NE(binary.find("'\\x01\\x7f'"), std::string::npos) << binary;
}

TEST(Config, StringsWithQuotesAndControlCharactersRoundTrip) {
  Config c;
  c.backend.opencl_device = "a\"b\\c\nd\te";
  c.backend.opencl_platform = "Portable: {x} #1";
  const Config back = Config::FromYaml(c.ToYaml(), "written.yaml");
  EXPECT_EQ(back.backend.opencl_device, c.backend.opencl_device);
  EXPECT_EQ(back.backend.opencl_platform, c.backend.opencl_platform);
  EXPECT_EQ(back.ToYaml(), c.ToYaml());
}

TEST(Config, TheOutlineRuleNeedsTheFullScanPolygon) {
  EXPECT_TRUE(Config().sensor_model.free_on_outline);  // the paper's rule by default
  EXPECT_EQ(ErrorOf("sensor_model:\n  free_on_outline: false\n"), "");
  const std::string conventional =
      ErrorOf("sensor_model:\n  kind: conventional\n  free_on_outline: false\n");
  EXPECT_NE(conventional.find("sensor_model.free_on_outline = false"), std::string::npos)
      << conventional;
  EXPECT_NE(conventional.find("sensor_model.kind enhanced"), std::string::npos) << conventional;
  EXPECT_EQ(ErrorOf("sensor_model:\n  kind: conventional\n"), "");
}

TEST(Config, PolygonMarginIsValidatedAndKept) {
  const Config defaults;
  EXPECT_EQ(defaults.polygon.margin_cells, 0);  // the paper's polygon: no margin
  const std::string inside = "polygon:\n  shape: inside\n";
  EXPECT_EQ(ErrorOf(inside + "  margin_cells: 1\n  margin_cone_deg: 60\n"), "");
  EXPECT_NE(ErrorOf(inside + "  margin_cells: -1\n").find("polygon.margin_cells = -1"),
            std::string::npos);
  EXPECT_NE(ErrorOf(inside + "  margin_cells: 33\n").find("polygon.margin_cells = 33"),
            std::string::npos);
  const std::string paper = ErrorOf("polygon:\n  margin_cells: 2\n");
  EXPECT_NE(paper.find("polygon.margin_cells = 2"), std::string::npos) << paper;
  EXPECT_NE(paper.find("polygon.shape inside"), std::string::npos) << paper;
  EXPECT_NE(ErrorOf(inside + "  margin_cone_deg: 0\n").find("polygon.margin_cone_deg = 0"),
            std::string::npos);
  EXPECT_NE(ErrorOf(inside + "  margin_cone_deg: 181\n").find("polygon.margin_cone_deg = 181"),
            std::string::npos);
  EXPECT_EQ(ErrorOf(inside + "  face_tolerance_m: 0.05\n"), "");
  EXPECT_NE(ErrorOf(inside + "  face_tolerance_m: -0.1\n").find("polygon.face_tolerance_m = -0.1"),
            std::string::npos);
  EXPECT_NE(ErrorOf(inside + "  face_tolerance_m: 2\n").find("polygon.face_tolerance_m = 2"),
            std::string::npos);
  const std::string faces = ErrorOf("polygon:\n  face_tolerance_m: 0.05\n");
  EXPECT_NE(faces.find("polygon.shape inside"), std::string::npos) << faces;
  const std::string rays =
      ErrorOf(inside + "  face_tolerance_m: 0.05\nsensor_model:\n  kind: conventional\n");
  EXPECT_EQ(ErrorOf(inside + "  mover_memory_s: 3\n"), "");
  EXPECT_NE(ErrorOf(inside + "  mover_memory_s: -1\n").find("polygon.mover_memory_s = -1"),
            std::string::npos);
  EXPECT_NE(ErrorOf(inside + "  mover_memory_s: 11\n").find("polygon.mover_memory_s = 11"),
            std::string::npos);
  const std::string movers = ErrorOf("polygon:\n  mover_memory_s: 3\n");
  EXPECT_NE(movers.find("polygon.mover_memory_s"), std::string::npos) << movers;
  EXPECT_NE(movers.find("polygon.shape inside"), std::string::npos) << movers;
  EXPECT_NE(rays.find("sensor_model.kind enhanced"), std::string::npos) << rays;
  Config c;
  c.polygon.shape = PolygonShape::kInside;
  c.polygon.margin_cells = 3;
  c.polygon.margin_cone_deg = 45.5;
  c.polygon.face_tolerance_m = 0.07;
  c.polygon.mover_memory_s = 2.5;
  const Config back = Config::FromYaml(c.ToYaml());
  EXPECT_EQ(back.polygon.margin_cells, 3);
  EXPECT_DOUBLE_EQ(back.polygon.margin_cone_deg, 45.5);
  EXPECT_DOUBLE_EQ(back.polygon.face_tolerance_m, 0.07);
  EXPECT_DOUBLE_EQ(back.polygon.mover_memory_s, 2.5);
}

TEST(Config, ThresholdsAgreeWithProbabilitiesOnEveryLogOdds) {
  for (const double t : {0.05, 0.3, 0.42, 0.48, 0.4999}) {
    const LogOdds threshold = LogOddsThreshold(t);
    for (int l = -2000; l <= 2000; ++l) {
      ASSERT_EQ(l <= threshold, ProbabilityFromLogOdds(LogOdds(l)) <= t) << t << " " << l;
    }
  }
}

TEST(Config, OpeningElementIsAnOddSquareAboutTheVehicleWidth) {
  Config c;
  EXPECT_EQ(MakeKernelParams(c).opening_radius, 4);  // 1.8 m / 0.2 m = 9 cells
  c.classify.vehicle_width_m = 0.4;
  EXPECT_EQ(MakeKernelParams(c).opening_radius, 1);  // 3 cells
  c.classify.vehicle_width_m = 0.0;
  EXPECT_EQ(MakeKernelParams(c).opening_radius, 0);
}

// docs/configuration.md holds the field table's rows (ConfigFieldsMarkdown) between these lines.
constexpr const char* kDocsBegin =
    "<!-- BEGIN fields: generated from the field table in src/core/config_table.hpp; "
    "tests/config_test.cpp checks them -->\n";
constexpr const char* kDocsEnd = "<!-- END fields -->\n";

TEST(ConfigDocs, ConfigurationMdListsEveryFieldAsTheTableDoes) {
  const std::string path = "docs/configuration.md";
  std::string text = test::ReadSourceFile(path);
  const std::size_t begin = text.find(kDocsBegin), end = text.find(kDocsEnd);
  ASSERT_NE(begin, std::string::npos) << path << " lacks the line " << kDocsBegin;
  ASSERT_NE(end, std::string::npos) << path << " lacks the line " << kDocsEnd;
  ASSERT_LT(begin, end);
  const std::size_t rows = begin + std::string(kDocsBegin).size();
  const std::string expected = ConfigFieldsMarkdown();
  if (text.compare(rows, end - rows, expected) != 0 && std::getenv("FREESPACE_UPDATE_DOCS")) {
    text.replace(rows, end - rows, expected);
    std::ofstream(test::SourcePath(path)) << text;
    GTEST_SKIP() << "rewrote the field rows of " << test::SourcePath(path);
  }
  // Name the first line that differs rather than print both blocks whole.
  std::istringstream have(text.substr(rows, end - rows)), want(expected);
  for (int line = 1;; ++line) {
    std::string a, b;
    const bool more_a = bool(std::getline(have, a)), more_b = bool(std::getline(want, b));
    if (!more_a && !more_b) break;
    ASSERT_EQ(a, b)
        << path << ": line " << line << " of the field rows differs from the field "
        << "table (src/core/config_table.hpp); run this test with FREESPACE_UPDATE_DOCS=1 "
        << "to rewrite the rows";
  }
}

TEST(ConfigDocs, EveryFieldHasATypeADocAndAValidDefault) {
  std::set<std::string> names;
  for (const ConfigFieldDoc& d : ConfigFieldDocs()) {
    EXPECT_TRUE(names.insert(d.name).second) << d.name << " listed twice";
    EXPECT_NE(d.name.find('.'), std::string::npos) << d.name;
    EXPECT_FALSE(d.type.empty()) << d.name;
    EXPECT_FALSE(d.doc.empty()) << d.name;
    EXPECT_FALSE(d.default_value.empty()) << d.name;
    if (d.type == "integer" || d.type == "number") {
      EXPECT_FALSE(d.range.empty()) << d.name;
    }
  }
  EXPECT_EQ(ConfigFieldNames().size(), names.size());
  // Every field reads back from its section, so the names are the YAML keys.
  const YAML::Node written = YAML::Load(Config().ToYaml());
  for (const std::string& name : ConfigFieldNames()) {
    const std::size_t dot = name.find('.');
    EXPECT_TRUE(written[name.substr(0, dot)][name.substr(dot + 1)].IsDefined()) << name;
  }
}

TEST(ConfigDocs, RangeErrorsComeFromTheTable) {
  EXPECT_NE(ErrorOf("map:\n  width_cells: 1\n").find("map.width_cells = 1: must be in [2, 8192]"),
            std::string::npos);
  EXPECT_NE(ErrorOf("clutter:\n  eps_per_m: 1\n").find("clutter.eps_per_m = 1: must be in [0, 1)"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf("alignment:\n  max_speed_mps: 0\n").find("alignment.max_speed_mps = 0: must be > 0"),
      std::string::npos);
  EXPECT_NE(ErrorOf("alignment:\n  gain_s: .inf\n").find("alignment.gain_s = inf: must be finite"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sensor:\n  max_angle_deg: .nan\n")
                .find("sensor.max_angle_deg = nan: must be finite"),
            std::string::npos);
  EXPECT_NE(ErrorOf("classify:\n  t_low: 0.45\n  t_high: 0.44\n")
                .find("classify.t_high = 0.44: must be >= classify.t_low"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sensor:\n  min_angle_deg: 10\n  max_angle_deg: 5\n")
                .find("sensor.max_angle_deg = 5: must be in (sensor.min_angle_deg"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sensor:\n  max_range_m: 5000\n").find("sensor.max_range_m = 5000: must keep"),
            std::string::npos);
  EXPECT_NE(ErrorOf("sensor:\n  max_range_m: 5000\n").find("the scan reaches 25300 cells"),
            std::string::npos);
  // A beam spacing that leaves more beams than the preprocessing can hold room for is refused
  // with the count, not found out by an allocation; 0.01 deg over 145 deg and 4 layers passes.
  EXPECT_NE(ErrorOf("sensor:\n  angular_resolution_deg: 1e-6\n")
                .find("sensor.angular_resolution_deg = 1e-06: must leave at most 1048576 beams a "
                      "scan"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("sensor:\n  angular_resolution_deg: 0.01\n"), "");
  // A sensor's name is one printable word, the one sensor's as a rig's.
  EXPECT_NE(ErrorOf("sensor:\n  name: a b\n").find("sensor.name = \"a b\": must be one word"),
            std::string::npos);
  EXPECT_EQ(ErrorOf("sensor:\n  name: vorn_\xc3\xa4\n"), "");  // UTF-8 letters are taken
  EXPECT_NE(ErrorOf("sensor:\n  name: ''\n").find("sensor.name is empty"), std::string::npos);
  // A reach past any integer (the config fuzzer's find: the message cast it to int) is told as
  // it is.
  EXPECT_NE(ErrorOf("sensor:\n  max_range_m: 1e136\n").find("the scan reaches 5e+136 cells"),
            std::string::npos);
  Config c;
  c.backend.kind = BackendKind(7);
  try {
    c.Validate();
    ADD_FAILURE() << "an enum value out of its names passed";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("backend.kind = 7: must be one of tbb | opencl | auto"),
              std::string::npos)
        << e.what();
  }
}

// configs/scala.yaml is the full reference config: every field set, each to its default but
// the sensor's mount and the polygon's settings (its header says which and why).
TEST(ConfigDocs, ScalaYamlSetsEveryFieldToItsDefaultButTheNamedOnes) {
  const std::string text = test::ReadSourceFile("configs/scala.yaml");
  const YAML::Node root = YAML::Load(text);
  const Config scala = test::LoadProjectConfig("scala.yaml");
  const YAML::Node values = YAML::Load(scala.ToYaml()), defaults = YAML::Load(Config().ToYaml());
  const std::set<std::string> not_default = {
      "sensor.mount_x_m",        "sensor.sweep_s",
      "polygon.shape",           "polygon.max_vertices",
      "polygon.epsilon_m",       "polygon.margin_cells",
      "polygon.margin_cone_deg", "polygon.face_tolerance_m",
      "polygon.mover_memory_s",  "sensor_model.free_on_outline"};
  for (const std::string& name : ConfigFieldNames()) {
    const std::string section = name.substr(0, name.find('.'));
    const std::string field = name.substr(name.find('.') + 1);
    EXPECT_TRUE(root[section][field].IsDefined()) << "configs/scala.yaml does not set " << name;
    const bool same = values[section][field].Scalar() == defaults[section][field].Scalar();
    EXPECT_EQ(same, !not_default.count(name))
        << name << " = " << values[section][field].Scalar() << " in configs/scala.yaml, default "
        << defaults[section][field].Scalar();
  }
}

// The other project configs are valid and set only fields the table knows (FromYaml checks).
TEST(ConfigDocs, ProjectConfigsAreValid) {
  const Config indoor = test::LoadProjectConfig("indoor.yaml");
  EXPECT_DOUBLE_EQ(indoor.classify.vehicle_width_m, 0.4);
  EXPECT_DOUBLE_EQ(indoor.alignment.max_speed_mps, 5.0);
  EXPECT_DOUBLE_EQ(indoor.alignment.jump_slack_m, 1.0);
}

}  // namespace
}  // namespace freespace
