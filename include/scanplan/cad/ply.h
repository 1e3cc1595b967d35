#pragma once
// PLY files (Turk's polygon file format) as scanplan reads and writes them: elements of
// scalar and list properties. Read: ascii, binary_little_endian and binary_big_endian;
// written: binary_little_endian, which MeshLab, CloudCompare and Blender read.

#include <cstdint>
#include <string>
#include <vector>

namespace scanplan {

enum class PlyType : std::uint8_t { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::Float32;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  // of a list
  std::vector<double> values;           // scalar: one per item of its element
  std::vector<std::vector<int>> lists;  // list: one per item
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;

  // The property named `name`, or null.
  const PlyProperty* find(const std::string& name) const;
  // Adds a scalar property; `values` must hold `count` items.
  void add(const std::string& name, PlyType type, std::vector<double> values);
};

struct PlyData {
  std::vector<std::string> comments;
  std::vector<PlyElement> elements;

  // The element named `name`, or null.
  const PlyElement* find(const std::string& name) const;
};

// \throw InputError naming the file: missing, not PLY, unknown type or format, truncated.
PlyData readPly(const std::string& path);

// Writes binary little-endian PLY through a temporary file renamed into place.
// \throw OutputError when it cannot be written.
void writePly(const PlyData& data, const std::string& path);

// The column `name` of `element` of a file read by readPly.
// \throw InputError naming `path` when the element or property is missing.
const std::vector<double>& plyColumn(const PlyData& data, const std::string& element,
                                     const std::string& name, const std::string& path);

}  // namespace scanplan
