#pragma once
// The scanner of a YAML document already read: the spec reads its `scanner` key so. And
// the reading of a file that must hold one YAML document, for scanner files and specs.

#include <scanplan/scanner/sensor.h>

#include <yaml-cpp/yaml.h>

#include <string>

namespace scanplan {

// The one YAML document of `text`. \throw InputError naming `source` when it holds more
// than one (split by ---; yaml-cpp would read the first alone), saying it is `what` ("a
// spec"); YAML::Exception when it is no YAML.
YAML::Node loadOneDocument(const std::string& text, const std::string& source,
                           const std::string& what);

// loadScanner on the document `root`; errors name `source`.
Scanner scannerFromYaml(const YAML::Node& root, const std::string& source);

}  // namespace scanplan
