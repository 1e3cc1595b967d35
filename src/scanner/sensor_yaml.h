#pragma once
// The scanner of a YAML document already read: the spec reads its `scanner` key so.

#include <scanplan/scanner/sensor.h>

#include <yaml-cpp/yaml.h>

#include <string>

namespace scanplan {

// loadScanner on the document `root`; errors name `source`.
Scanner scannerFromYaml(const YAML::Node& root, const std::string& source);

}  // namespace scanplan
