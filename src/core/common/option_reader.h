// Reads typed options from a YAML mapping with range checks, in one place per options struct.
// Missing keys keep the struct's default; present keys of the wrong type or out of range throw
// LoadError naming the full key path ("icgm.threshold: 3.5 not in [0, 1]"). Unknown keys are
// reported by UnusedKeys(), and the loaders that gather a file's sections make them an error with
// RejectUnknownKeys() so a typo in a config file does not pass silently.
#pragma once

#include <initializer_list>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/common/enum_names.h"
#include "core/common/status.h"

namespace icgm {

class OptionReader {
 public:
  // Loads a YAML file; throws LoadError when missing or unparsable.
  static OptionReader FromFile(const std::string& path);
  static OptionReader FromString(const std::string& yaml_text);
  OptionReader(YAML::Node node, std::string path_prefix);

  // Records, by full key path ("icgm.threshold"), the value each Read/ReadChoice finds in the
  // options struct before reading: over an empty mapping, the struct's defaults. Sections share
  // the record. Lets a test compare the code's defaults with the shipped YAML.
  using DefaultsRecord = std::map<std::string, YAML::Node>;
  static OptionReader Recording(std::shared_ptr<DefaultsRecord> record);

  bool Has(const std::string& key) const;
  // Sub-section; an absent section gives an empty reader (all defaults).
  OptionReader Section(const std::string& key) const;

  void Read(const std::string& key, double* value, double min, double max) const;
  void Read(const std::string& key, int* value, int min, int max) const;
  void Read(const std::string& key, bool* value) const;
  void Read(const std::string& key, std::string* value) const;
  // One of an enum's choices, spelt as its EnumNames table spells them (enum_names.h); any other
  // string is an error naming the key and listing the allowed values
  // ("features.detector: 'orbb' is not one of {orb, sift, akaze, gftt_orb, surf}").
  template <typename E>
  void ReadEnum(const std::string& key, E* value) const {
    std::string text = NameOf(*value);
    ReadChoice(key, &text, EnumChoices<E>());
    *value = *ParseEnum<E>(text);
  }

  // Keys present in this mapping (not recursively) that no Read/Section call asked for.
  std::vector<std::string> UnusedKeys() const;
  // Throws LoadError naming every unused key ("unknown key 'frontend.use_icmg'"); call after all
  // reads of this mapping.
  void RejectUnknownKeys() const;
  static void RejectUnknownKeys(std::initializer_list<const OptionReader*> readers);
  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }

 private:
  std::string Full(const std::string& key) const;
  // A string restricted to `choices` (ReadEnum's untyped part).
  void ReadChoice(const std::string& key, std::string* value,
                  const std::vector<std::string>& choices) const;
  template <typename T>
  void Record(const std::string& key, const T& value) const;
  YAML::Node node_;
  std::string path_;
  mutable std::set<std::string> used_;
  std::shared_ptr<DefaultsRecord> record_;  // null unless Recording()
};

}  // namespace icgm
