// The configuration file: every key round-trips, every key refuses what its range refuses (with
// the file, the line and the key), and the defaults are the library's own.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "loopscan/config/config_file.hpp"
#include "loopscan/config/keys.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan {
namespace {

namespace fs = std::filesystem;
using config_keys::Range;

// Every key of the file: its dotted path, what kind of value it takes and its range.
struct KeyInfo {
  std::string path;
  enum Kind { Number, Whole, Optional, List, WholeList, Bool, Enum, MethodName } kind;
  Range range;
};

class KeyLister {
 public:
  std::vector<KeyInfo> keys;

  template <typename Body>
  void section(const char* name, const char*, Body body) {
    prefix_.push_back(name);
    body();
    prefix_.pop_back();
  }
  void key(const char* n, double&, const Range& r, const char*) { add(n, KeyInfo::Number, r); }
  void key(const char* n, float&, const Range& r, const char*) { add(n, KeyInfo::Number, r); }
  void key(const char* n, int&, const Range& r, const char*) { add(n, KeyInfo::Whole, r); }
  void key(const char* n, unsigned&, const Range& r, const char*) { add(n, KeyInfo::Whole, r); }
  void key(const char* n, std::optional<double>&, const Range& r, const char*) {
    add(n, KeyInfo::Optional, r);
  }
  void key(const char* n, std::vector<double>&, const Range& r, const char*) {
    add(n, KeyInfo::List, r);
  }
  void key(const char* n, std::vector<int>&, const Range& r, const char*) {
    add(n, KeyInfo::WholeList, r);
  }
  void key(const char* n, bool&, const char*) { add(n, KeyInfo::Bool, {}); }
  template <typename E>
  void key(const char* n, E&, const char*) {
    add(n, KeyInfo::Enum, {});
  }
  void method_key(const char* n, Configuration&, const char*) { add(n, KeyInfo::MethodName, {}); }

 private:
  void add(const char* name, KeyInfo::Kind kind, const Range& r) {
    std::string p;
    for (const std::string& s : prefix_) p += s + ".";
    keys.push_back({p + name, kind, r});
  }
  std::vector<std::string> prefix_;
};

std::vector<KeyInfo> all_keys() {
  KeyLister lister;
  Configuration c;
  config_keys::visit(lister, c);
  return lister.keys;
}

// A YAML document setting one dotted key to `value` (the key on the last line).
std::string yaml_setting(const std::string& path, const std::string& value) {
  std::istringstream parts(path);
  std::string part, text;
  std::vector<std::string> names;
  while (std::getline(parts, part, '.')) names.push_back(part);
  for (std::size_t i = 0; i < names.size(); ++i) {
    text += std::string(2 * i, ' ') + names[i] + ":";
    text += i + 1 == names.size() ? " " + value + "\n" : "\n";
  }
  return text;
}

class ConfigFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("loopscan_config_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string file(const std::string& text, const std::string& name = "c.yaml") {
    const std::string p = (dir_ / name).string();
    std::ofstream(p) << text;
    return p;
  }
  // The message of the InputError loading `text` throws, or "" when it loads.
  std::string error(const std::string& text, const std::string& method = "sc",
                    Mode mode = Mode::Default) {
    const std::string p = file(text);
    try {
      load_configuration(p, method, mode);
    } catch (const io::InputError& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_;
};

TEST_F(ConfigFile, TheDefaultsAreTheLibrarysOwn) {
  for (Mode mode : {Mode::Default, Mode::Reference}) {
    for (Method method : {Method::ScanContext, Method::M2dp, Method::Delight}) {
      const Configuration c = Configuration::defaults(method, mode);
      const SequenceOptions made = SequenceOptions::make(method, mode);
      const SequenceOptions built = sequence_options(c);
      EXPECT_EQ(built.imitation.range_m, made.imitation.range_m);
      EXPECT_EQ(built.imitation.mode, mode);
      EXPECT_EQ(built.descriptors.scan_context.frame, made.descriptors.scan_context.frame);
      EXPECT_EQ(built.descriptors.scan_context.lateral_versions_m,
                made.descriptors.scan_context.lateral_versions_m);
      EXPECT_EQ(built.descriptors.m2dp.mode, mode);
      const closure::LoopCloserConfig closer = loop_closer_config(c);
      const closure::LoopCloserConfig made_closer = closure::LoopCloserConfig::make(method, mode);
      EXPECT_EQ(closer.recognition.descriptors.scan_context.frame,
                made_closer.recognition.descriptors.scan_context.frame);
      EXPECT_EQ(closer.recognition.descriptors.scan_context.lateral_versions_m,
                made_closer.recognition.descriptors.scan_context.lateral_versions_m);
      EXPECT_EQ(closer.recognition.query.exclude_recent,
                made_closer.recognition.query.exclude_recent);
      EXPECT_EQ(closer.max_candidate_distance, made_closer.max_candidate_distance);
      EXPECT_EQ(closer.verify.min_overlap, made_closer.verify.min_overlap);
      EXPECT_EQ(closer.graph.loop_translation_m, made_closer.graph.loop_translation_m);
      const eval::PlaceEvaluationOptions e = place_evaluation_options(c, false);
      EXPECT_EQ(e.fusion, default_fusion(mode));
      EXPECT_EQ(e.reference_quirks, mode == Mode::Reference);
      EXPECT_EQ(place_evaluation_options(c, true).protocol.threshold_m, 25.0);
      EXPECT_EQ(lane_query_options(c).reverse_window_rad, LaneQueryOptions{}.reverse_window_rad);
      EXPECT_EQ(database_config(c).fusion, DatabaseConfig{}.fusion);
      EXPECT_NO_THROW(validate(c));
    }
  }
}

// The open-road settings shipped for the CLI are the library's preset, key for key.
TEST(OpenRoadConfig, TheShippedFileIsTheLibrarysPreset) {
  const std::string path = std::string(LOOPSCAN_SOURCE_DIR) + "/docs/experiments/open-road.yaml";
  const Configuration c = load_configuration(path, "sc", Mode::Default);
  EXPECT_EQ(sim::to_json(c.simulator.world).dump(1),
            sim::to_json(sim::open_road_world_config()).dump(1));
  EXPECT_NE(sim::to_json(sim::WorldConfig{}), sim::to_json(sim::open_road_world_config()));
}

// Dump, load: the same document; and the dump of every method and mode loads as itself.
TEST_F(ConfigFile, DumpLoadRoundTripIsExact) {
  for (const char* method : {"sc", "m2dp", "delight", "gist", "bow"}) {
    for (Mode mode : {Mode::Default, Mode::Reference}) {
      const Configuration c = Configuration::defaults(method, mode);
      const std::string text = configuration_yaml(c, "a header\nof two lines");
      EXPECT_EQ(text.rfind("# a header\n# of two lines\n", 0), 0u);
      const FileChoice choice = read_file_choice(file(text));
      ASSERT_TRUE(choice.method && choice.mode);
      EXPECT_EQ(*choice.method, method);
      EXPECT_EQ(*choice.mode, mode);
      const Configuration back = load_configuration(file(text), method, mode);
      EXPECT_EQ(configuration_yaml(back), configuration_yaml(c)) << method;
    }
  }
}

// Editing any key of the dump changes that value and nothing else (numbers: a value inside the
// range; bools flipped; enums to another name).
TEST_F(ConfigFile, EveryEditedKeyIsLoaded) {
  const Configuration defaults = Configuration::defaults();
  const std::string base = configuration_yaml(defaults);
  int edited = 0;
  for (const KeyInfo& k : all_keys()) {
    std::vector<std::string> values;  // tried in turn until one differs from the default
    const auto text = [](double v) {
      std::ostringstream o;
      o.precision(17);
      o << v;
      return o.str();
    };
    switch (k.kind) {
      case KeyInfo::Number:
      case KeyInfo::Optional:
        if (std::isfinite(k.range.hi) && k.range.hi < 1e6) values.push_back(text(k.range.hi));
        if (std::isfinite(k.range.lo) && std::isfinite(k.range.hi))
          values.push_back(text((k.range.lo + k.range.hi) / 2));
        values.push_back("7");
        break;
      case KeyInfo::Whole:
        if (k.range.hi < 100) values.push_back(std::to_string(int(k.range.hi)));
        values.push_back(std::to_string(int(k.range.lo) + 1));
        values.push_back("9");
        break;
      case KeyInfo::List:
      case KeyInfo::WholeList:
        values = {"[]", "[1]"};
        break;
      case KeyInfo::Bool:
      case KeyInfo::Enum:
      case KeyInfo::MethodName:
        continue;  // below, by name
    }
    bool changed = false;
    for (const std::string& value : values) {
      Configuration c;
      try {
        c = load_configuration(file(yaml_setting(k.path, value)), "sc", Mode::Default);
      } catch (const io::InputError& e) {
        // A value valid alone may break a rule between keys: the message names the section.
        const std::string m = e.what();
        const std::string section = k.path.substr(0, k.path.find('.'));
        EXPECT_NE(m.find("consistent configuration"), std::string::npos) << k.path << ": " << m;
        EXPECT_NE(m.find(section), std::string::npos) << k.path << ": " << m;
        changed = true;
        break;
      }
      if (configuration_yaml(c) != base) {
        changed = true;
        ++edited;
        break;
      }
    }
    EXPECT_TRUE(changed) << k.path << ": no value changed the configuration";
  }
  EXPECT_GT(edited, 100);
  const Configuration flipped = load_configuration(
      file("descriptors:\n  scan_context:\n    max_height: true\n    frame: centroid\n"
           "database:\n  storage: compact\n  query:\n    retrieval: exact\n"
           "evaluation:\n  fusion: structure\nsimulator:\n  illumination:\n    gain: null\n"
           "    gamma: 0.5\n"),
      "sc", Mode::Default);
  EXPECT_TRUE(flipped.descriptors.scan_context.max_height);
  EXPECT_EQ(flipped.descriptors.scan_context.frame, DescriptorFrame::Centroid);
  EXPECT_EQ(flipped.database.storage, PlaceStorage::Compact);
  EXPECT_EQ(flipped.database.query.retrieval, Retrieval::Exact);
  EXPECT_EQ(flipped.evaluation.fusion, Fusion::Structure);
  EXPECT_FALSE(flipped.simulator.illumination_gain.has_value());
  EXPECT_EQ(flipped.simulator.gamma, 0.5);
  // A misspelt method is named with the closest one.
  EXPECT_THROW(Configuration::defaults("m2pd", Mode::Default), std::invalid_argument);
  try {
    Configuration::defaults("m2pd", Mode::Default);
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'm2dp'?"), std::string::npos) << e.what();
  }
  // What a file leaves out keeps the defaults of its method and mode.
  const Configuration partial =
      load_configuration(file("closure:\n  candidates: 5\n"), "m2dp", Mode::Reference);
  EXPECT_EQ(partial.closure.closer.candidates, 5);
  EXPECT_EQ(partial.evaluation.fusion, Fusion::Fused);  // the paper's, in reference mode
  EXPECT_EQ(partial.method, Method::M2dp);
}

// Every numeric key refuses values outside its range, a key of the wrong type, and the message
// names the file, the line of the value and the key.
TEST_F(ConfigFile, EveryKeyRefusesWhatItsRangeRefuses) {
  int checked = 0;
  for (const KeyInfo& k : all_keys()) {
    std::vector<std::string> bad;
    switch (k.kind) {
      case KeyInfo::Number:
      case KeyInfo::Optional:
        if (std::isfinite(k.range.hi)) bad.push_back(std::to_string(k.range.hi * 2 + 1));
        if (std::isfinite(k.range.lo)) bad.push_back(std::to_string(k.range.lo - 1));
        if (k.range.lo_open) bad.push_back(std::to_string(k.range.lo));
        bad.push_back("nan");
        bad.push_back("ten");
        bad.push_back("[1, 2]");
        break;
      case KeyInfo::Whole:
        if (std::isfinite(k.range.hi)) bad.push_back(std::to_string((long long)(k.range.hi) + 1));
        bad.push_back(std::to_string((long long)(k.range.lo) - 1));
        bad.push_back("1.5");
        bad.push_back("{a: 1}");
        break;
      case KeyInfo::List:
      case KeyInfo::WholeList:
        bad.push_back("[" + std::to_string(k.range.hi * 2 + 1) + "]");
        bad.push_back("3");
        bad.push_back("[x]");
        break;
      case KeyInfo::Bool:
        bad = {"maybe", "1"};
        break;
      case KeyInfo::Enum:
      case KeyInfo::MethodName:
        bad = {"bogus"};
        break;
    }
    for (const std::string& value : bad) {
      const std::string text = yaml_setting(k.path, value);
      const std::size_t line = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
      std::string m;
      if (k.kind == KeyInfo::MethodName) {
        try {
          read_file_choice(file(text));
        } catch (const io::InputError& e) {
          m = e.what();
        }
      } else {
        m = error(text);
      }
      ASSERT_FALSE(m.empty()) << k.path << ": " << value << " was accepted";
      const std::string where = (dir_ / "c.yaml").string() + ":" + std::to_string(line) + ":";
      EXPECT_EQ(m.rfind(where, 0), 0u) << m;
      const std::string leaf = k.path.substr(k.path.rfind('.') + 1);
      EXPECT_NE(m.find(k.kind == KeyInfo::MethodName ? "method" : k.path), std::string::npos) << m;
      ++checked;
    }
  }
  EXPECT_GT(checked, 500);
}

TEST_F(ConfigFile, UnknownDuplicateAndMalformedKeysAreRefused) {
  std::string m = error("imitation:\n  range: 45\n");
  EXPECT_NE(m.find("c.yaml:2: expected a key of 'imitation'"), std::string::npos) << m;
  EXPECT_NE(m.find("got 'range' (did you mean 'range_m'?)"), std::string::npos) << m;
  m = error("closure:\n  verification:\n    min_overlapp: 0.3\n");
  EXPECT_NE(m.find("c.yaml:3:"), std::string::npos) << m;
  EXPECT_NE(m.find("'closure.verification'"), std::string::npos) << m;
  EXPECT_NE(m.find("did you mean 'min_overlap'"), std::string::npos) << m;
  m = error("imitaton:\n  range_m: 45\n");
  EXPECT_NE(m.find("c.yaml:1: expected a key of the top level"), std::string::npos) << m;
  m = error("closure:\n  candidates: 2\n  candidates: 3\n");
  EXPECT_NE(m.find("c.yaml:3: expected each key once, got 'candidates' again in 'closure'"),
            std::string::npos)
      << m;
  m = error("closure: [1, 2]\n");
  EXPECT_NE(m.find("c.yaml:1: expected a map of keys for closure"), std::string::npos) << m;
  m = error("closure:\n  candidates: [1\n");
  EXPECT_NE(m.find("c.yaml:"), std::string::npos) << m;
  EXPECT_NE(m.find("valid YAML"), std::string::npos) << m;
  m = error("- a\n- b\n");
  EXPECT_NE(m.find("c.yaml:1: expected a YAML map of configuration keys"), std::string::npos) << m;
  m = error("closure:\n  candidates:\n");
  EXPECT_NE(m.find("c.yaml:2: expected a single value for closure.candidates, got 'nothing'"),
            std::string::npos)
      << m;
  EXPECT_EQ(error(""), "");  // an empty file keeps every default
  EXPECT_EQ(error("# only a comment\n"), "");
  EXPECT_EQ(error("closure:\n"), "");  // an empty section too
  // A missing file.
  try {
    load_configuration((dir_ / "none.yaml").string(), "sc", Mode::Default);
    ADD_FAILURE() << "a missing file loaded";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none.yaml"), std::string::npos);
  }
}

// Values each in range but contradicting the mode or each other name the key and its line.
TEST_F(ConfigFile, RulesBetweenKeysNameTheKey) {
  std::string m =
      error("descriptors:\n  scan_context:\n    frame: camera\n", "sc", Mode::Reference);
  EXPECT_NE(m.find("descriptors.*.frame: reference mode is the paper's PCA frame"),
            std::string::npos)
      << m;
  EXPECT_NE(m.find("c.yaml:1:"), std::string::npos) << m;
  m = error("imitation:\n  lookahead_m: 20\n", "sc", Mode::Reference);
  EXPECT_NE(m.find("c.yaml:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("imitation.lookahead_m: reference mode is the paper's forward-only scan"),
            std::string::npos)
      << m;
  m = error("descriptors:\n  scan_context:\n    frame: pca\n");
  EXPECT_NE(m.find("lateral_versions_m needs the default mode and the camera or centroid frame"),
            std::string::npos)
      << m;
  m = error("database:\n  fusion: adaptive\n");
  EXPECT_NE(m.find("c.yaml:2:"), std::string::npos) << m;
  EXPECT_NE(m.find("database.fusion"), std::string::npos) << m;
  m = error("vo:\n  window_keyframes: 3\n  fixed_keyframes: 3\n");
  EXPECT_NE(m.find("vo.fixed_keyframes: fewer than vo.window_keyframes"), std::string::npos) << m;
  // The file's method and mode must be what the caller decided (read_file_choice).
  EXPECT_THROW(load_configuration(file("mode: reference\n"), "sc", Mode::Default),
               std::logic_error);
}

}  // namespace
}  // namespace loopscan
