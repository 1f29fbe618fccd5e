#include "pipeline/io/schema_validator.h"

#include <H5Lpublic.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

namespace fogpipe::io {
namespace {

using hdf5::ObjectKind;
using hdf5::TypeClass;
using Json = nlohmann::json;

constexpr const char* kSchemaFormat = "fogpipe-schema-v1";

// ---------------------------------------------------------------- parsed rules

/// A name or a name pattern: "<axis>" matches one path component, "<k:int>" decimal digits.
struct NameRule {
  std::string key;
  bool is_pattern = false;
  std::regex regex;
  bool Matches(const std::string& name) const {
    return is_pattern ? std::regex_match(name, regex) : name == key;
  }
};

struct TypeRule {
  std::vector<TypeClass> allowed;  ///< empty: any
  std::string text;                ///< as written in the schema, for messages
  bool Accepts(TypeClass t) const {
    return allowed.empty() || std::find(allowed.begin(), allowed.end(), t) != allowed.end();
  }
};

struct AttributeRule {
  NameRule name;
  bool required = false;
  TypeRule type;
  std::vector<int> ranks;  ///< empty: any
  std::vector<Json> enum_values;
  std::optional<std::regex> pattern;
  std::string pattern_text;
  std::optional<double> minimum, maximum, exclusive_minimum, exclusive_maximum;
  bool finite = false;
  std::optional<int> length_equals_dim;
};

/// What groups and datasets share: a name (or pattern), presence and count, attributes.
struct ObjectRule {
  NameRule name;
  bool required = false;
  std::optional<long long> min_count, max_count;
  std::vector<AttributeRule> attributes;
  bool forbid_additional_attributes = false;
};

/// A field of a table (a compound dataset): name, type, required.
struct FieldRule {
  std::string name;
  TypeRule type;
  bool required = true;
};

struct DatasetRule : ObjectRule {
  TypeRule type;
  std::vector<FieldRule> fields;  ///< of a compound dataset; additional fields are accepted
  std::vector<int> ranks;
  bool units_required = false;
  std::vector<std::string> units_allowed;
  std::string same_length_as;
};

/// An external link among a group's children: accepted as a reference to another file, never
/// followed (a validator of one file reads nothing else).
struct LinkRule : ObjectRule {
  std::optional<std::string> target;  ///< the object path inside the linked file
};

struct GroupRule : ObjectRule {
  std::vector<GroupRule> groups;
  std::vector<DatasetRule> datasets;
  std::vector<LinkRule> links;
  bool forbid_additional = false;
};

// ---------------------------------------------------------------- parsing

class Parser {
 public:
  explicit Parser(std::string origin) : origin_(std::move(origin)) {}

  [[noreturn]] void Fail(const std::string& where, const std::string& what) const {
    throw SchemaError("schema " + origin_ + ": " + where + ": " + what);
  }

  void CheckKeys(const Json& node, const std::string& where, const std::set<std::string>& keys) {
    if (!node.is_object()) Fail(where, "must be a JSON object");
    for (const auto& item : node.items()) {
      if (!keys.count(item.key())) Fail(where, "unknown key '" + item.key() + "'");
    }
  }

  NameRule ParseName(const std::string& key, const std::string& where) {
    NameRule rule;
    rule.key = key;
    std::string regex;
    size_t i = 0;
    while (i < key.size()) {
      if (key[i] == '<') {
        const size_t close = key.find('>', i);
        if (close == std::string::npos) Fail(where, "unclosed '<' in name pattern '" + key + "'");
        const std::string placeholder = key.substr(i + 1, close - i - 1);
        const size_t colon = placeholder.find(':');
        const std::string kind = colon == std::string::npos ? "" : placeholder.substr(colon + 1);
        if (kind.empty()) {
          regex += "[^/]+";
        } else if (kind == "int") {
          regex += "[0-9]+";
        } else {
          Fail(where, "unknown placeholder kind '" + kind + "' in '" + key +
                          "' (use <name> or <name:int>)");
        }
        rule.is_pattern = true;
        i = close + 1;
      } else {
        if (std::string("\\^$.|?*+()[]{}").find(key[i]) != std::string::npos) regex += '\\';
        regex += key[i];
        ++i;
      }
    }
    if (rule.is_pattern) rule.regex = std::regex(regex);
    return rule;
  }

  TypeRule ParseType(const Json& value, const std::string& where) {
    TypeRule rule;
    std::vector<std::string> names;
    if (value.is_string()) {
      names.push_back(value.get<std::string>());
    } else if (value.is_array()) {
      for (const Json& v : value) {
        if (!v.is_string()) Fail(where, "'type' entries must be strings");
        names.push_back(v.get<std::string>());
      }
    } else {
      Fail(where, "'type' must be a string or an array of strings");
    }
    for (const std::string& n : names) {
      if (n == "float") {
        rule.allowed.push_back(TypeClass::kFloat);
      } else if (n == "integer") {
        rule.allowed.push_back(TypeClass::kInteger);
      } else if (n == "number") {
        rule.allowed.push_back(TypeClass::kFloat);
        rule.allowed.push_back(TypeClass::kInteger);
      } else if (n == "string") {
        rule.allowed.push_back(TypeClass::kString);
      } else if (n == "compound") {
        rule.allowed.push_back(TypeClass::kCompound);
      } else {
        Fail(where, "unknown type '" + n + "' (float, integer, number, string, compound)");
      }
      rule.text += (rule.text.empty() ? "" : " or ") + n;
    }
    return rule;
  }

  std::vector<int> ParseRanks(const Json& value, const std::string& where) {
    std::vector<int> ranks;
    if (value.is_number_integer()) {
      ranks.push_back(value.get<int>());
    } else if (value.is_array()) {
      for (const Json& v : value) {
        if (!v.is_number_integer()) Fail(where, "'rank' entries must be integers");
        ranks.push_back(v.get<int>());
      }
    } else {
      Fail(where, "'rank' must be an integer or an array of integers");
    }
    return ranks;
  }

  std::optional<double> OptionalNumber(const Json& node, const char* key,
                                       const std::string& where) {
    if (!node.contains(key)) return std::nullopt;
    if (!node[key].is_number()) Fail(where, std::string("'") + key + "' must be a number");
    return node[key].get<double>();
  }

  std::optional<long long> OptionalCount(const Json& node, const char* key,
                                         const std::string& where) {
    if (!node.contains(key)) return std::nullopt;
    if (!node[key].is_number_integer())
      Fail(where, std::string("'") + key + "' must be an integer");
    return node[key].get<long long>();
  }

  bool OptionalBool(const Json& node, const char* key, const std::string& where, bool fallback) {
    if (!node.contains(key)) return fallback;
    if (!node[key].is_boolean()) Fail(where, std::string("'") + key + "' must be true or false");
    return node[key].get<bool>();
  }

  bool ParseAdditional(const Json& node, const char* key, const std::string& where) {
    if (!node.contains(key)) return false;
    const std::string value = node[key].is_string() ? node[key].get<std::string>() : "";
    if (value != "ignore" && value != "forbid")
      Fail(where, std::string("'") + key + "' must be \"ignore\" or \"forbid\"");
    return value == "forbid";
  }

  AttributeRule ParseAttribute(const std::string& key, const Json& node, const std::string& where) {
    CheckKeys(node, where,
              {"description", "required", "type", "rank", "enum", "pattern", "minimum", "maximum",
               "exclusive_minimum", "exclusive_maximum", "finite", "length_equals_dim"});
    AttributeRule rule;
    rule.name = ParseName(key, where);
    rule.required = OptionalBool(node, "required", where, false);
    if (node.contains("type")) rule.type = ParseType(node["type"], where);
    if (node.contains("rank")) rule.ranks = ParseRanks(node["rank"], where);
    if (node.contains("enum")) {
      if (!node["enum"].is_array()) Fail(where, "'enum' must be an array");
      for (const Json& v : node["enum"]) rule.enum_values.push_back(v);
    }
    if (node.contains("pattern")) {
      if (!node["pattern"].is_string()) Fail(where, "'pattern' must be a string");
      rule.pattern_text = node["pattern"].get<std::string>();
      try {
        rule.pattern = std::regex(rule.pattern_text, std::regex::ECMAScript);
      } catch (const std::regex_error& e) {
        Fail(where, "bad 'pattern' regex: " + std::string(e.what()));
      }
    }
    rule.minimum = OptionalNumber(node, "minimum", where);
    rule.maximum = OptionalNumber(node, "maximum", where);
    rule.exclusive_minimum = OptionalNumber(node, "exclusive_minimum", where);
    rule.exclusive_maximum = OptionalNumber(node, "exclusive_maximum", where);
    rule.finite = OptionalBool(node, "finite", where, false);
    if (node.contains("length_equals_dim")) {
      if (!node["length_equals_dim"].is_number_integer())
        Fail(where, "'length_equals_dim' must be an integer");
      rule.length_equals_dim = node["length_equals_dim"].get<int>();
    }
    return rule;
  }

  std::vector<AttributeRule> ParseAttributes(const Json& node, const std::string& where) {
    std::vector<AttributeRule> rules;
    if (!node.is_object()) Fail(where, "'attributes' must be an object");
    for (const auto& item : node.items()) {
      rules.push_back(ParseAttribute(item.key(), item.value(), where + "/@" + item.key()));
    }
    return rules;
  }

  void ParseCommon(const std::string& key, const Json& node, const std::string& where,
                   ObjectRule* rule) {
    rule->name = ParseName(key, where);
    rule->required = OptionalBool(node, "required", where, false);
    rule->min_count = OptionalCount(node, "min_count", where);
    rule->max_count = OptionalCount(node, "max_count", where);
    if (node.contains("attributes")) rule->attributes = ParseAttributes(node["attributes"], where);
    rule->forbid_additional_attributes = ParseAdditional(node, "additional_attributes", where);
  }

  DatasetRule ParseDataset(const std::string& key, const Json& node, const std::string& where) {
    CheckKeys(node, where,
              {"description", "required", "min_count", "max_count", "type", "rank", "attributes",
               "additional_attributes", "units", "same_length_as", "fields"});
    DatasetRule rule;
    ParseCommon(key, node, where, &rule);
    if (node.contains("type")) rule.type = ParseType(node["type"], where);
    if (node.contains("fields")) {
      if (!node["fields"].is_object()) Fail(where, "'fields' must be an object");
      for (const auto& item : node["fields"].items()) {
        const std::string field_where = where + "/" + item.key();
        if (!item.value().is_object()) Fail(field_where, "a field must be an object");
        CheckKeys(item.value(), field_where, {"description", "required", "type"});
        FieldRule field;
        field.name = item.key();
        field.required = OptionalBool(item.value(), "required", field_where, true);
        if (item.value().contains("type"))
          field.type = ParseType(item.value()["type"], field_where);
        rule.fields.push_back(std::move(field));
      }
    }
    if (node.contains("rank")) rule.ranks = ParseRanks(node["rank"], where);
    if (node.contains("units")) {
      const Json& units = node["units"];
      if (units.is_boolean()) {
        rule.units_required = units.get<bool>();
      } else if (units.is_array()) {
        rule.units_required = true;
        for (const Json& u : units) {
          if (!u.is_string()) Fail(where, "'units' entries must be strings");
          rule.units_allowed.push_back(u.get<std::string>());
        }
      } else {
        Fail(where, "'units' must be true, false or an array of allowed strings");
      }
    }
    if (node.contains("same_length_as")) {
      if (!node["same_length_as"].is_string()) Fail(where, "'same_length_as' must be a path");
      rule.same_length_as = node["same_length_as"].get<std::string>();
    }
    return rule;
  }

  LinkRule ParseLink(const std::string& key, const Json& node, const std::string& where) {
    CheckKeys(node, where, {"description", "required", "min_count", "max_count", "target"});
    LinkRule rule;
    ParseCommon(key, node, where, &rule);
    if (node.contains("target")) {
      if (!node["target"].is_string()) Fail(where, "'target' must be a path");
      rule.target = node["target"].get<std::string>();
    }
    return rule;
  }

  GroupRule ParseGroup(const std::string& key, const Json& node, const std::string& where) {
    CheckKeys(node, where,
              {"description", "required", "min_count", "max_count", "attributes",
               "additional_attributes", "groups", "datasets", "links", "additional"});
    GroupRule rule;
    ParseCommon(key, node, where, &rule);
    rule.forbid_additional = ParseAdditional(node, "additional", where);
    if (node.contains("groups")) {
      if (!node["groups"].is_object()) Fail(where, "'groups' must be an object");
      for (const auto& item : node["groups"].items()) {
        rule.groups.push_back(ParseGroup(item.key(), item.value(), where + "/" + item.key()));
      }
    }
    if (node.contains("datasets")) {
      if (!node["datasets"].is_object()) Fail(where, "'datasets' must be an object");
      for (const auto& item : node["datasets"].items()) {
        rule.datasets.push_back(ParseDataset(item.key(), item.value(), where + "/" + item.key()));
      }
    }
    if (node.contains("links")) {
      if (!node["links"].is_object()) Fail(where, "'links' must be an object");
      for (const auto& item : node["links"].items()) {
        rule.links.push_back(ParseLink(item.key(), item.value(), where + "/" + item.key()));
      }
    }
    return rule;
  }

 private:
  std::string origin_;
};

// ---------------------------------------------------------------- validation

std::string JoinPath(const std::string& parent, const std::string& name) {
  return parent == "/" ? "/" + name : parent + "/" + name;
}

std::string RankText(const std::vector<int>& ranks) {
  std::string text;
  for (size_t i = 0; i < ranks.size(); ++i) text += (i ? " or " : "") + std::to_string(ranks[i]);
  return text;
}

std::string ListText(const std::vector<std::string>& values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) text += (i ? ", " : "") + values[i];
  return text;
}

std::string NumberText(double v) {
  std::ostringstream out;
  out.precision(17);
  out << v;
  return out.str();
}

class Validator {
 public:
  Validator(const hdf5::Group& root, ValidationReport* report, bool every_numeric_has_units)
      : root_(root), report_(report), every_numeric_has_units_(every_numeric_has_units) {}

  void Problem(const std::string& object, const std::string& message) {
    if (seen_.insert(object + '\n' + message).second)
      report_->problems.push_back({object, message});
  }

  void CheckAttributes(const hdf5::Object& object, const std::vector<AttributeRule>& rules,
                       bool forbid_additional, const std::vector<hsize_t>* dataset_dims) {
    const std::vector<std::string> names = object.AttributeNames();
    std::vector<bool> matched(names.size(), false);
    for (const AttributeRule& rule : rules) {
      long long count = 0;
      for (size_t i = 0; i < names.size(); ++i) {
        if (!rule.name.Matches(names[i])) continue;
        matched[i] = true;
        ++count;
        CheckAttribute(object, names[i], rule, dataset_dims);
      }
      if (count == 0 && rule.required) {
        Problem(object.path(), "missing required attribute '" + rule.name.key + "'");
      }
    }
    for (size_t i = 0; i < names.size(); ++i) {
      if (!matched[i] && forbid_additional) {
        Problem(object.path(), "unexpected attribute '" + names[i] + "'");
      }
    }
  }

  void CheckAttribute(const hdf5::Object& object, const std::string& name,
                      const AttributeRule& rule, const std::vector<hsize_t>* dataset_dims) {
    ++report_->objects_checked;
    const std::string prefix = "attribute '" + name + "' ";
    const hdf5::AttributeInfo info = object.DescribeAttribute(name);
    if (!rule.type.Accepts(info.type.type_class)) {
      Problem(object.path(), prefix + "has type " + hdf5::ToString(info.type.type_class) +
                                 ", expected " + rule.type.text);
      return;
    }
    const int rank = static_cast<int>(info.dims.size());
    if (!rule.ranks.empty() &&
        std::find(rule.ranks.begin(), rule.ranks.end(), rank) == rule.ranks.end()) {
      Problem(object.path(), prefix + "has rank " + std::to_string(rank) + ", expected rank " +
                                 RankText(rule.ranks));
      return;
    }
    if (rule.length_equals_dim && dataset_dims) {
      const int dim = *rule.length_equals_dim;
      if (dim < static_cast<int>(dataset_dims->size()) && info.size() != (*dataset_dims)[dim]) {
        Problem(object.path(), prefix + "has " + std::to_string(info.size()) +
                                   " elements, expected " + std::to_string((*dataset_dims)[dim]) +
                                   " (the dataset's extent in dimension " + std::to_string(dim) +
                                   ")");
      }
    }
    if (info.type.type_class == TypeClass::kString) {
      for (const std::string& value : object.ReadStringArrayAttribute(name)) {
        if (!rule.enum_values.empty() && std::find(rule.enum_values.begin(), rule.enum_values.end(),
                                                   Json(value)) == rule.enum_values.end()) {
          std::vector<std::string> allowed;
          for (const Json& v : rule.enum_values)
            allowed.push_back(v.is_string() ? v.get<std::string>() : v.dump());
          Problem(object.path(), prefix + "is '" + value + "', not one of " + ListText(allowed));
        }
        if (rule.pattern && !std::regex_match(value, *rule.pattern)) {
          Problem(object.path(),
                  prefix + "is '" + value + "', which does not match " + rule.pattern_text);
        }
      }
    } else if (info.type.type_class == TypeClass::kFloat ||
               info.type.type_class == TypeClass::kInteger) {
      for (double v : object.ReadDoubleArrayAttribute(name))
        CheckNumber(object.path(), prefix, v, rule);
    }
  }

  void CheckNumber(const std::string& path, const std::string& prefix, double v,
                   const AttributeRule& rule) {
    const std::string value = NumberText(v);
    if (rule.finite && !std::isfinite(v))
      Problem(path, prefix + "is " + value + ", expected a finite number");
    if (rule.minimum && !(v >= *rule.minimum))
      Problem(path, prefix + "is " + value + ", expected >= " + NumberText(*rule.minimum));
    if (rule.maximum && !(v <= *rule.maximum))
      Problem(path, prefix + "is " + value + ", expected <= " + NumberText(*rule.maximum));
    if (rule.exclusive_minimum && !(v > *rule.exclusive_minimum))
      Problem(path, prefix + "is " + value + ", expected > " + NumberText(*rule.exclusive_minimum));
    if (rule.exclusive_maximum && !(v < *rule.exclusive_maximum))
      Problem(path, prefix + "is " + value + ", expected < " + NumberText(*rule.exclusive_maximum));
    if (!rule.enum_values.empty() &&
        std::none_of(rule.enum_values.begin(), rule.enum_values.end(),
                     [v](const Json& e) { return e.is_number() && e.get<double>() == v; })) {
      Problem(path, prefix + "is " + value + ", not one of the allowed values");
    }
  }

  void CheckUnits(const hdf5::Dataset& dataset, bool required,
                  const std::vector<std::string>& allowed) {
    if (!dataset.HasAttribute(hdf5::kUnitsAttribute)) {
      if (required) Problem(dataset.path(), "numeric dataset has no 'units' attribute");
      return;
    }
    const hdf5::AttributeInfo info = dataset.DescribeAttribute(hdf5::kUnitsAttribute);
    if (info.type.type_class != TypeClass::kString || info.size() != 1) {
      Problem(dataset.path(), "attribute 'units' must be one string");
      return;
    }
    const std::string units = dataset.ReadStringAttribute(hdf5::kUnitsAttribute);
    if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), units) == allowed.end()) {
      Problem(dataset.path(),
              "units '" + units + "' not allowed here (allowed: " + ListText(allowed) + ")");
    }
  }

  void CheckFields(const hdf5::Dataset& dataset, const std::vector<FieldRule>& rules) {
    const auto fields = dataset.Fields();
    for (const FieldRule& rule : rules) {
      const auto field = std::find_if(fields.begin(), fields.end(),
                                      [&rule](const auto& f) { return f.first == rule.name; });
      if (field == fields.end()) {
        if (rule.required) Problem(dataset.path(), "missing required field '" + rule.name + "'");
        continue;
      }
      if (!rule.type.Accepts(field->second.type_class)) {
        Problem(dataset.path(), "field '" + rule.name + "' has type " +
                                    hdf5::ToString(field->second.type_class) + ", expected " +
                                    rule.type.text);
      }
    }
  }

  void CheckDataset(const hdf5::Dataset& dataset, const DatasetRule* rule) {
    ++report_->objects_checked;
    const hdf5::TypeInfo type = dataset.type();
    const std::vector<hsize_t> dims = dataset.dims();
    const bool numeric =
        type.type_class == TypeClass::kFloat || type.type_class == TypeClass::kInteger;
    if (numeric && every_numeric_has_units_) CheckUnits(dataset, true, {});
    if (!rule) return;
    if (!rule->type.Accepts(type.type_class)) {
      Problem(dataset.path(), std::string("has type ") + hdf5::ToString(type.type_class) +
                                  ", expected " + rule->type.text);
    }
    if (!rule->fields.empty() && type.type_class == TypeClass::kCompound) {
      CheckFields(dataset, rule->fields);
    }
    const int rank = static_cast<int>(dims.size());
    if (!rule->ranks.empty() &&
        std::find(rule->ranks.begin(), rule->ranks.end(), rank) == rule->ranks.end()) {
      Problem(dataset.path(),
              "has rank " + std::to_string(rank) + ", expected rank " + RankText(rule->ranks));
    }
    CheckAttributes(dataset, rule->attributes, rule->forbid_additional_attributes, &dims);
    if (rule->units_required || !rule->units_allowed.empty()) {
      CheckUnits(dataset, rule->units_required, rule->units_allowed);
    }
    if (!rule->same_length_as.empty() && !dims.empty()) {
      // A name without '/' is a sibling: the columns of a table inside a repeated group.
      const std::string& own = dataset.path();
      const std::string parent = own.substr(0, std::max<std::size_t>(own.rfind('/'), 1));
      const std::string other_path = rule->same_length_as[0] == '/'
                                         ? rule->same_length_as
                                         : JoinPath(parent, rule->same_length_as);
      if (root_.TraceLinks(other_path).end == hdf5::LinkTrace::End::kInFile &&
          root_.KindOf(other_path) == ObjectKind::kDataset) {
        const std::vector<hsize_t> other = root_.OpenDataset(other_path).dims();
        if (!other.empty() && other[0] != dims[0]) {
          Problem(dataset.path(), "has " + std::to_string(dims[0]) + " rows but " + other_path +
                                      " has " + std::to_string(other[0]));
        }
      }
    }
  }

  /// Checks `group` against `rule` (nullptr: an unknown group, only the file-wide rules apply).
  void CheckGroup(const hdf5::Group& group, const GroupRule* rule) {
    ++report_->objects_checked;
    if (rule) CheckAttributes(group, rule->attributes, rule->forbid_additional_attributes, nullptr);
    const std::vector<std::string> children = group.ChildNames();
    std::map<const ObjectRule*, long long> counts;
    for (const std::string& child : children) {
      const std::string path = JoinPath(group.path(), child);
      try {
        CheckChild(group, child, path, rule, &counts);
      } catch (const hdf5::Error& e) {
        Problem(path, "cannot be read: " + e.innermost_message());
      }
    }
    if (!rule) return;
    auto check_count = [&](const ObjectRule& r, const char* what) {
      const long long n = counts.count(&r) ? counts[&r] : 0;
      const std::string label = std::string(what) + " '" + r.name.key + "'";
      if (n == 0 && r.required) {
        Problem(group.path(), "missing required " + label);
      } else if (r.min_count && n < *r.min_count) {
        Problem(group.path(), "has " + std::to_string(n) + " " + label + ", expected at least " +
                                  std::to_string(*r.min_count));
      }
      if (r.max_count && n > *r.max_count) {
        Problem(group.path(), "has " + std::to_string(n) + " " + label + ", expected at most " +
                                  std::to_string(*r.max_count));
      }
    };
    for (const GroupRule& g : rule->groups) check_count(g, "group");
    for (const DatasetRule& d : rule->datasets) check_count(d, "dataset");
    for (const LinkRule& l : rule->links) check_count(l, "external link");
  }

  /// The link rule of `rule` matching `child`, exact names first; nullptr when none.
  static const LinkRule* LinkRuleNamed(const GroupRule* rule, const std::string& child) {
    if (!rule) return nullptr;
    for (bool patterns : {false, true}) {
      for (const LinkRule& l : rule->links) {
        if (l.name.is_pattern == patterns && l.name.Matches(child)) return &l;
      }
    }
    return nullptr;
  }

  /// An external link the schema describes: counted and its target checked, not followed.
  /// False when `child` is no external link or no rule describes it.
  bool CheckDescribedLink(const hdf5::Group& group, const std::string& child,
                          const std::string& path, const GroupRule* rule,
                          std::map<const ObjectRule*, long long>* counts) {
    const LinkRule* link_rule = LinkRuleNamed(rule, child);
    if (!link_rule) return false;
    H5L_info_t info;
    if (H5Lget_info(group.id(), child.c_str(), &info, H5P_DEFAULT) < 0 ||
        info.type != H5L_TYPE_EXTERNAL)
      return false;
    ++report_->objects_checked;
    ++(*counts)[link_rule];
    std::vector<char> value(info.u.val_size);
    const char* file_name = nullptr;
    const char* object = nullptr;
    unsigned flags = 0;
    if (H5Lget_val(group.id(), child.c_str(), value.data(), value.size(), H5P_DEFAULT) < 0 ||
        H5Lunpack_elink_val(value.data(), value.size(), &flags, &file_name, &object) < 0) {
      Problem(path, "external link that cannot be read");
    } else if (link_rule->target && *link_rule->target != object) {
      Problem(path, "external link to '" + std::string(object) + "' in " + file_name +
                        ", expected '" + *link_rule->target + "'");
    }
    return true;
  }

  /// The rule of `rule` whose name matches `child`, of either kind, exact names first.
  static const ObjectRule* RuleNamed(const GroupRule* rule, const std::string& child) {
    if (!rule) return nullptr;
    for (bool patterns : {false, true}) {
      for (const GroupRule& g : rule->groups) {
        if (g.name.is_pattern == patterns && g.name.Matches(child)) return &g;
      }
      for (const DatasetRule& d : rule->datasets) {
        if (d.name.is_pattern == patterns && d.name.Matches(child)) return &d;
      }
    }
    return nullptr;
  }

  void CheckChild(const hdf5::Group& group, const std::string& child, const std::string& path,
                  const GroupRule* rule, std::map<const ObjectRule*, long long>* counts) {
    // Looking an object up through an external link opens the file it names: a validator of one
    // file reads nothing else, so such a link is reported, never followed.
    // The tags are the reader's error kinds for the same links (recording_error.h).
    const hdf5::LinkTrace trace = root_.TraceLinks(path);
    if (trace.end == hdf5::LinkTrace::End::kLeavesFile && trace.link == path &&
        CheckDescribedLink(group, child, path, rule, counts))
      return;
    if (trace.end != hdf5::LinkTrace::End::kInFile) {
      if (trace.end == hdf5::LinkTrace::End::kLeavesFile) {
        Problem(path, "is reached through an external link (" + trace.link +
                          "), to data outside the file; not followed [external_data]");
      } else {
        Problem(path, "goes through more than " + std::to_string(hdf5::LinkTrace::kMaxSoftLinks) +
                          " soft links (a link cycle?); not followed [wrong_type]");
      }
      // It still stands for the object of its name: that one is not also "missing".
      if (const ObjectRule* named = RuleNamed(rule, child)) ++(*counts)[named];
      return;
    }
    const ObjectKind kind = group.KindOf(child);
    const GroupRule* group_rule = nullptr;
    const DatasetRule* dataset_rule = nullptr;
    if (rule) {
      // Exact names before patterns; within each, a rule of the child's own kind first. Only
      // when no rule of its kind matches does a rule of the other kind apply (a mismatch).
      for (bool patterns : {false, true}) {
        for (bool same_kind : {true, false}) {
          if (group_rule || dataset_rule) break;
          const bool want_group = (kind == ObjectKind::kGroup) == same_kind;
          if (want_group) {
            for (const GroupRule& g : rule->groups) {
              if (!group_rule && g.name.is_pattern == patterns && g.name.Matches(child))
                group_rule = &g;
            }
          } else {
            for (const DatasetRule& d : rule->datasets) {
              if (!dataset_rule && d.name.is_pattern == patterns && d.name.Matches(child))
                dataset_rule = &d;
            }
          }
        }
        if (group_rule || dataset_rule) break;
      }
    }
    if (group_rule) ++(*counts)[group_rule];
    if (dataset_rule) ++(*counts)[dataset_rule];
    if (kind == ObjectKind::kGroup) {
      if (dataset_rule) {
        Problem(path, "is a group, expected a dataset");
        return;
      }
      if (!group_rule && rule && rule->forbid_additional) Problem(path, "unexpected group");
      // A group reached through a soft link is the same object as its target, checked where it
      // is; following it would loop forever on a link cycle (/g/loop -> /g).
      H5L_info_t link;
      if (H5Lget_info(group.id(), child.c_str(), &link, H5P_DEFAULT) >= 0 &&
          link.type == H5L_TYPE_SOFT)
        return;
      CheckGroup(group.OpenGroup(child), group_rule);
    } else if (kind == ObjectKind::kDataset) {
      if (group_rule) {
        Problem(path, "is a dataset, expected a group");
        return;
      }
      if (!dataset_rule && rule && rule->forbid_additional) Problem(path, "unexpected dataset");
      CheckDataset(group.OpenDataset(child), dataset_rule);
    } else if (group_rule || dataset_rule || (rule && rule->forbid_additional)) {
      Problem(path, "is neither a group nor a dataset (named datatype or dangling link)");
    }
  }

 private:
  const hdf5::Group& root_;
  ValidationReport* report_;
  bool every_numeric_has_units_;
  std::set<std::string> seen_;
};

std::string ExecutableFolder() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::string() : exe.parent_path().string();
}

/// True if `path` is `folder` or lies below it (both resolved, so symlinks and ".." compare equal).
bool IsInside(const std::string& path, const std::string& folder) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
  const std::filesystem::path f = std::filesystem::weakly_canonical(folder, ec);
  if (ec) return false;
  const auto mismatch = std::mismatch(f.begin(), f.end(), p.begin(), p.end());
  return mismatch.first == f.end();
}

}  // namespace

struct Schema::Impl {
  std::string name;
  std::string title;
  bool every_numeric_dataset_has_units = false;
  GroupRule root;
};

Schema::Schema(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Schema::Schema(Schema&&) noexcept = default;
Schema& Schema::operator=(Schema&&) noexcept = default;
Schema::~Schema() = default;

const std::string& Schema::name() const { return impl_->name; }
const std::string& Schema::title() const { return impl_->title; }

Schema Schema::FromJsonText(const std::string& text, const std::string& origin) {
  Json document;
  try {
    document = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw SchemaError("schema " + origin + ": not valid JSON: " + e.what());
  }
  Parser parser(origin);
  parser.CheckKeys(
      document, "top level",
      {"format", "name", "title", "description", "every_numeric_dataset_has_units", "root"});
  if (!document.contains("format") || document["format"] != kSchemaFormat) {
    parser.Fail("top level", std::string("'format' must be \"") + kSchemaFormat + "\"");
  }
  if (!document.contains("name") || !document["name"].is_string())
    parser.Fail("top level", "'name' (a string) is required");
  if (!document.contains("root")) parser.Fail("top level", "'root' (the root group) is required");
  auto impl = std::make_unique<Impl>();
  impl->name = document["name"].get<std::string>();
  impl->title = document.value("title", "");
  impl->every_numeric_dataset_has_units =
      parser.OptionalBool(document, "every_numeric_dataset_has_units", "top level", false);
  impl->root = parser.ParseGroup("/", document["root"], "root");
  return Schema(std::move(impl));
}

Schema Schema::FromFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SchemaError("schema " + path + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  return FromJsonText(text.str(), path);
}

ValidationReport Schema::Validate(const hdf5::File& file) const {
  ValidationReport report;
  report.file = file.path();
  report.schema = impl_->name;
  try {
    const hdf5::Group root = file.Root();
    Validator validator(root, &report, impl_->every_numeric_dataset_has_units);
    validator.CheckGroup(root, &impl_->root);
  } catch (const hdf5::Error& e) {
    report.problems.push_back(
        {e.object().empty() ? "/" : e.object(), "cannot be read: " + e.innermost_message()});
  }
  return report;
}

std::vector<std::string> SchemaSearchPath(const std::string& explicit_dir) {
  std::vector<std::string> path;
  if (!explicit_dir.empty()) path.push_back(explicit_dir);
  if (const char* env = std::getenv("FOGPIPE_SCHEMAS_DIR"); env && *env) path.push_back(env);
  const std::string exe = ExecutableFolder();
  if (!exe.empty()) path.push_back(exe + "/" + FOGPIPE_SCHEMAS_FROM_BINDIR);
  // The source tree is looked at only by a binary of this build tree: an installed copy must
  // never pick up whatever a stale checkout on the build machine holds.
  if (!exe.empty() && IsInside(exe, FOGPIPE_BUILD_DIR)) path.push_back(FOGPIPE_SCHEMAS_DIR);
  return path;
}

std::string FindSchemaFile(const std::string& name, const std::string& explicit_dir) {
  const std::vector<std::string> folders = SchemaSearchPath(explicit_dir);
  // An explicit --schemas folder is the only place looked at: a typo must not silently fall back.
  const size_t count = explicit_dir.empty() ? folders.size() : 1;
  for (size_t i = 0; i < count; ++i) {
    const std::filesystem::path candidate = std::filesystem::path(folders[i]) / (name + ".json");
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) return candidate.string();
  }
  return "";
}

}  // namespace fogpipe::io
