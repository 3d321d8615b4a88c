#include "core/common/option_reader.h"

#include <sstream>

namespace icgm {

OptionReader OptionReader::FromFile(const std::string& path) {
  try {
    return OptionReader(YAML::LoadFile(path), "");
  } catch (const YAML::BadFile&) {
    throw LoadError("cannot open config file '" + path + "'");
  } catch (const YAML::Exception& e) {
    throw LoadError("config file '" + path + "' is not valid YAML: " + e.what());
  }
}

OptionReader OptionReader::FromString(const std::string& yaml_text) {
  try {
    return OptionReader(YAML::Load(yaml_text), "");
  } catch (const YAML::Exception& e) {
    throw LoadError(std::string("config text is not valid YAML: ") + e.what());
  }
}

OptionReader OptionReader::Recording(std::shared_ptr<DefaultsRecord> record) {
  OptionReader reader(YAML::Node(), "");
  reader.record_ = std::move(record);
  return reader;
}

template <typename T>
void OptionReader::Record(const std::string& key, const T& value) const {
  if (record_) (*record_)[Full(key)] = YAML::Node(value);
}

OptionReader::OptionReader(YAML::Node node, std::string path_prefix)
    : node_(std::move(node)), path_(std::move(path_prefix)) {
  if (node_ && !node_.IsNull() && !node_.IsMap()) {
    throw LoadError("config section '" + (path_.empty() ? std::string("<root>") : path_) +
                    "' must be a mapping");
  }
}

std::string OptionReader::Full(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool OptionReader::Has(const std::string& key) const {
  return node_ && node_.IsMap() && node_[key];
}

OptionReader OptionReader::Section(const std::string& key) const {
  used_.insert(key);
  OptionReader section(Has(key) ? node_[key] : YAML::Node(), Full(key));
  section.record_ = record_;
  return section;
}

namespace {
template <typename T>
T As(const YAML::Node& n, const std::string& full, const char* type_name) {
  try {
    return n.as<T>();
  } catch (const YAML::Exception&) {
    std::ostringstream s;
    s << full << ": expected " << type_name << ", got '" << YAML::Dump(n) << "'";
    throw LoadError(s.str());
  }
}
}  // namespace

void OptionReader::Read(const std::string& key, double* value, double min, double max) const {
  used_.insert(key);
  Record(key, *value);
  if (!Has(key)) return;
  const double v = As<double>(node_[key], Full(key), "a number");
  if (!(v >= min && v <= max)) {
    std::ostringstream s;
    s << Full(key) << ": " << v << " not in [" << min << ", " << max << "]";
    throw LoadError(s.str());
  }
  *value = v;
}

void OptionReader::Read(const std::string& key, int* value, int min, int max) const {
  used_.insert(key);
  Record(key, *value);
  if (!Has(key)) return;
  const int v = As<int>(node_[key], Full(key), "an integer");
  if (v < min || v > max) {
    std::ostringstream s;
    s << Full(key) << ": " << v << " not in [" << min << ", " << max << "]";
    throw LoadError(s.str());
  }
  *value = v;
}

void OptionReader::Read(const std::string& key, bool* value) const {
  used_.insert(key);
  Record(key, *value);
  if (!Has(key)) return;
  *value = As<bool>(node_[key], Full(key), "true or false");
}

void OptionReader::Read(const std::string& key, std::string* value) const {
  used_.insert(key);
  Record(key, *value);
  if (!Has(key)) return;
  *value = As<std::string>(node_[key], Full(key), "a string");
}

void OptionReader::ReadChoice(const std::string& key, std::string* value,
                              const std::vector<std::string>& choices) const {
  std::string v = *value;
  Read(key, &v);
  for (const auto& c : choices) {
    if (c == v) {
      *value = v;
      return;
    }
  }
  throw LoadError(Full(key) + ": " + NotOneOf(v, choices));
}

std::vector<std::string> OptionReader::UnusedKeys() const {
  std::vector<std::string> out;
  if (!node_ || !node_.IsMap()) return out;
  for (const auto& kv : node_) {
    const std::string k = kv.first.as<std::string>();
    if (!used_.count(k)) out.push_back(Full(k));
  }
  return out;
}

void OptionReader::RejectUnknownKeys() const {
  const std::vector<std::string> unused = UnusedKeys();
  if (unused.empty()) return;
  std::string message = unused.size() == 1 ? "unknown key '" : "unknown keys '";
  for (size_t i = 0; i < unused.size(); ++i) message += (i ? "', '" : "") + unused[i];
  throw LoadError(message + "' (misspelt, or not an option of this section)");
}

void OptionReader::RejectUnknownKeys(std::initializer_list<const OptionReader*> readers) {
  for (const OptionReader* r : readers) r->RejectUnknownKeys();
}

}  // namespace icgm
