// PLY reading and writing: a header of elements and properties, then the data of each
// element in turn, item by item.

#include <scanplan/cad/ply.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace scanplan {
namespace {

struct TypeName {
  PlyType type;
  const char* name;
  const char* alias;
  std::size_t size;
};
constexpr std::array<TypeName, 8> kTypes = {{
    {PlyType::Int8, "char", "int8", 1},
    {PlyType::UInt8, "uchar", "uint8", 1},
    {PlyType::Int16, "short", "int16", 2},
    {PlyType::UInt16, "ushort", "uint16", 2},
    {PlyType::Int32, "int", "int32", 4},
    {PlyType::UInt32, "uint", "uint32", 4},
    {PlyType::Float32, "float", "float32", 4},
    {PlyType::Float64, "double", "float64", 8},
}};

const TypeName& info(PlyType type) { return kTypes[static_cast<std::size_t>(type)]; }

bool parseType(const std::string& name, PlyType& type) {
  for (const TypeName& t : kTypes)
    if (name == t.name || name == t.alias) {
      type = t.type;
      return true;
    }
  return false;
}

class Reader {
 public:
  explicit Reader(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) fail("cannot open the file");
  }

  PlyData read() {
    readHeader();
    // Storage grows as items are read, so that a header claiming more items than the
    // file holds ends in "truncated", not in a huge allocation.
    constexpr std::size_t kReserve = 1 << 20;
    for (PlyElement& element : data_.elements) {
      if (element.properties.empty()) continue;  // its items take no bytes
      for (PlyProperty& p : element.properties) {
        if (p.is_list)
          p.lists.reserve(std::min(element.count, kReserve));
        else
          p.values.reserve(std::min(element.count, kReserve));
      }
      for (std::size_t i = 0; i < element.count; ++i) {
        startItem(element, i);
        for (PlyProperty& p : element.properties) {
          if (!p.is_list) {
            p.values.push_back(value(p.type));
            continue;
          }
          const double n = value(p.count_type);
          if (!(n >= 0 && n <= (1 << 20)))
            fail("a list of element '" + element.name + "' is too long");
          std::vector<int>& list = p.lists.emplace_back(static_cast<std::size_t>(n));
          for (int& item : list) {
            const double v = value(p.type);
            if (!(v >= std::numeric_limits<int>::min() && v <= std::numeric_limits<int>::max()))
              fail("a list of element '" + element.name + "' holds " + std::to_string(v) +
                   ", not an index");
            item = static_cast<int>(v);
          }
        }
        endItem();
      }
    }
    return std::move(data_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(path_, where_.empty() ? why : where_ + ": " + why);
  }

  // An ASCII item is one line: its values are read from it, and errors name it.
  void startItem(const PlyElement& element, std::size_t i) {
    where_.clear();
    std::string place = "element '" + element.name + "' item " + std::to_string(i + 1);
    if (format_ == "ascii") {
      std::string line;
      if (!std::getline(in_, line)) fail("truncated PLY file: " + place + " is missing");
      ++line_;
      item_.clear();
      item_.str(line);
      place = "line " + std::to_string(line_) + ", " + place;
    }
    where_ = place;
  }

  void endItem() {
    std::string rest;
    if (format_ == "ascii" && item_ >> rest) fail("more values than the element's properties");
    where_.clear();
  }

  void readHeader() {
    std::string line;
    if (!std::getline(in_, line) || line.substr(0, 3) != "ply")
      fail("not a PLY file: it does not begin with 'ply'");
    line_ = 1;
    while (std::getline(in_, line)) {
      ++line_;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (keyword == "format") {
        words >> format_;
        if (format_ != "ascii" && format_ != "binary_little_endian" &&
            format_ != "binary_big_endian")
          fail("unknown PLY format '" + format_ + "'");
      } else if (keyword == "comment") {
        data_.comments.push_back(line.size() > 8 ? line.substr(8) : std::string());
      } else if (keyword == "element") {
        PlyElement element;
        long count = -1;
        if (!(words >> element.name >> count) || count < 0)
          fail("malformed PLY element line: " + line);
        element.count = static_cast<std::size_t>(count);
        data_.elements.push_back(std::move(element));
      } else if (keyword == "property") {
        if (data_.elements.empty()) fail("PLY property before any element");
        PlyProperty property;
        std::string type;
        words >> type;
        if (type == "list") {
          property.is_list = true;
          std::string count_type;
          words >> count_type >> type;
          if (!parseType(count_type, property.count_type))
            fail("unknown PLY property type '" + count_type + "'");
        }
        if (!parseType(type, property.type)) fail("unknown PLY property type '" + type + "'");
        words >> property.name;
        data_.elements.back().properties.push_back(std::move(property));
      } else if (keyword == "end_header") {
        return;
      }
    }
    fail("truncated PLY file: no end_header");
  }

  double value(PlyType type) {
    if (format_ == "ascii") {
      double v;
      if (!(item_ >> v)) fail("fewer values than the element's properties, or one not a number");
      return v;
    }
    unsigned char bytes[8];
    const std::size_t size = info(type).size;
    if (!in_.read(reinterpret_cast<char*>(bytes), static_cast<std::streamsize>(size)))
      fail("truncated PLY file: the data ends before the header's counts");
    const bool big = format_ == "binary_big_endian";
    if (big != (std::endian::native == std::endian::big)) std::reverse(bytes, bytes + size);
    auto as = [&](auto v) {
      std::memcpy(&v, bytes, sizeof v);
      return static_cast<double>(v);
    };
    switch (type) {
      case PlyType::Int8: return as(std::int8_t{});
      case PlyType::UInt8: return as(std::uint8_t{});
      case PlyType::Int16: return as(std::int16_t{});
      case PlyType::UInt16: return as(std::uint16_t{});
      case PlyType::Int32: return as(std::int32_t{});
      case PlyType::UInt32: return as(std::uint32_t{});
      case PlyType::Float32: return as(float{});
      case PlyType::Float64: break;
    }
    return as(double{});
  }

  std::string path_;
  std::ifstream in_;
  std::istringstream item_;  // the ASCII item being read
  std::size_t line_ = 0;     // lines read
  std::string where_;        // the item being read, for errors
  std::string format_ = "ascii";
  PlyData data_;
};

// Appends `v` as `type`, little-endian.
void put(std::string& out, PlyType type, double v) {
  auto append = [&](auto x) {
    char bytes[sizeof x];
    std::memcpy(bytes, &x, sizeof x);
    if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof x);
    out.append(bytes, sizeof x);
  };
  switch (type) {
    case PlyType::Int8: return append(static_cast<std::int8_t>(v));
    case PlyType::UInt8: return append(static_cast<std::uint8_t>(v));
    case PlyType::Int16: return append(static_cast<std::int16_t>(v));
    case PlyType::UInt16: return append(static_cast<std::uint16_t>(v));
    case PlyType::Int32: return append(static_cast<std::int32_t>(v));
    case PlyType::UInt32: return append(static_cast<std::uint32_t>(v));
    case PlyType::Float32: return append(static_cast<float>(v));
    case PlyType::Float64: return append(v);
  }
}

}  // namespace

const PlyProperty* PlyElement::find(const std::string& property) const {
  for (const PlyProperty& p : properties)
    if (p.name == property) return &p;
  return nullptr;
}

void PlyElement::add(const std::string& property, PlyType type, std::vector<double> values) {
  PlyProperty p;
  p.name = property;
  p.type = type;
  p.values = std::move(values);
  p.values.resize(count);
  properties.push_back(std::move(p));
}

const PlyElement* PlyData::find(const std::string& element) const {
  for (const PlyElement& e : elements)
    if (e.name == element) return &e;
  return nullptr;
}

PlyData readPly(const std::string& path) { return Reader(path).read(); }

void writePly(const PlyData& data, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "ply\nformat binary_little_endian 1.0\n";
    for (const std::string& comment : data.comments) out << "comment " << comment << '\n';
    for (const PlyElement& element : data.elements) {
      out << "element " << element.name << ' ' << element.count << '\n';
      for (const PlyProperty& p : element.properties) {
        out << "property ";
        if (p.is_list) out << "list " << info(p.count_type).name << ' ';
        out << info(p.type).name << ' ' << p.name << '\n';
      }
    }
    out << "end_header\n";
    std::string buffer;
    for (const PlyElement& element : data.elements) {
      for (std::size_t i = 0; i < element.count; ++i) {
        for (const PlyProperty& p : element.properties) {
          if (!p.is_list) {
            put(buffer, p.type, p.values[i]);
            continue;
          }
          put(buffer, p.count_type, static_cast<double>(p.lists[i].size()));
          for (int item : p.lists[i]) put(buffer, p.type, item);
        }
        if (buffer.size() > (1 << 20)) {
          out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
          buffer.clear();
        }
      }
    }
    out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  });
}

const std::vector<double>& plyColumn(const PlyData& data, const std::string& element,
                                     const std::string& name, const std::string& path) {
  const PlyElement* e = data.find(element);
  if (e == nullptr) throw InputError(path, "no PLY element '" + element + "'");
  const PlyProperty* p = e->find(name);
  if (p == nullptr || p->is_list)
    throw InputError(path, "PLY element '" + element + "' has no property '" + name + "'");
  return p->values;
}

}  // namespace scanplan
