// The characteristics of a part's GD&T: one list of what the inspection verifies.

#include <scanplan/cad/gdt.h>

#include <algorithm>

namespace scanplan {
namespace {

std::vector<int> sortedUnique(std::vector<int> faces) {
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return faces;
}

}  // namespace

std::vector<Characteristic> characteristics(const Gdt& gdt) {
  std::vector<Characteristic> result;
  for (const GeometricTolerance& t : gdt.tolerances) {
    Characteristic c;
    c.id = static_cast<int>(result.size()) + 1;
    c.kind = t.type;
    c.value = t.value;
    c.upper = t.value;
    c.datums = t.datums;
    c.faces = sortedUnique(t.faces);
    result.push_back(std::move(c));
  }
  for (const Dimension& d : gdt.dimensions) {
    if (!(d.value > 0)) continue;  // a dimension without a value verifies nothing
    Characteristic c;
    c.id = static_cast<int>(result.size()) + 1;
    c.kind = d.type;
    c.dimension = true;
    c.value = d.value;
    c.lower = d.value - d.lower;
    c.upper = d.value + d.upper;
    c.faces = sortedUnique(d.faces);
    result.push_back(std::move(c));
  }
  return result;
}

std::vector<std::string> datumLetters(const std::string& reference) {
  std::vector<std::string> letters;
  std::size_t start = 0;
  for (std::size_t dash; (dash = reference.find('-', start)) != std::string::npos; start = dash + 1)
    letters.push_back(reference.substr(start, dash - start));
  letters.push_back(reference.substr(start));
  return letters;
}

std::vector<int> datumFaces(const Gdt& gdt, const std::string& reference) {
  std::vector<int> faces;
  for (const std::string& letter : datumLetters(reference))
    for (const Datum& d : gdt.datums)
      if (d.name == letter) faces.insert(faces.end(), d.faces.begin(), d.faces.end());
  return sortedUnique(faces);
}

std::vector<int> datumFaces(const Gdt& gdt, const Characteristic& c) {
  std::vector<int> faces;
  for (const std::string& reference : c.datums)
    for (int f : datumFaces(gdt, reference)) faces.push_back(f);
  return sortedUnique(faces);
}

bool datumsLinked(const Gdt& gdt, const Characteristic& c) {
  if (c.dimension) return true;
  return std::all_of(c.datums.begin(), c.datums.end(), [&](const std::string& reference) {
    const std::vector<std::string> letters = datumLetters(reference);
    return std::all_of(letters.begin(), letters.end(),
                       [&](const std::string& letter) { return !datumFaces(gdt, letter).empty(); });
  });
}

bool verifiable(const Gdt& gdt, const Characteristic& c) {
  return c.width() > 0 && !c.faces.empty() && datumsLinked(gdt, c);
}

std::vector<int> verifiedFaces(const Gdt& gdt) {
  std::vector<int> faces;
  for (const Characteristic& c : characteristics(gdt))
    if (verifiable(gdt, c)) faces.insert(faces.end(), c.faces.begin(), c.faces.end());
  return sortedUnique(faces);
}

std::vector<int> verifiedDatumFaces(const Gdt& gdt) {
  std::vector<int> faces;
  for (const Characteristic& c : characteristics(gdt))
    if (verifiable(gdt, c))
      for (int f : datumFaces(gdt, c)) faces.push_back(f);
  return sortedUnique(faces);
}

std::vector<int> judgedFaces(const Gdt& gdt) {
  std::vector<int> faces = verifiedFaces(gdt);
  const std::vector<int> datums = verifiedDatumFaces(gdt);
  faces.insert(faces.end(), datums.begin(), datums.end());
  return sortedUnique(faces);
}

}  // namespace scanplan
