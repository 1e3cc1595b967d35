#include <scanplan/core/atomic_file.h>
#include <scanplan/io/pgm.h>

#include <algorithm>
#include <cmath>
#include <ostream>

namespace scanplan {

void writePgm(const VisibilityMap& map, const std::string& path) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "P5\n# scanplan combined visibility map: azimuth across, elevation up\n"
        << map.azimuths << ' ' << map.elevations << "\n255\n";
    const double top = std::max<std::uint32_t>(map.max(), 1);
    for (int e = map.elevations - 1; e >= 0; --e)
      for (int a = 0; a < map.azimuths; ++a)
        out.put(static_cast<char>(std::lround(255 * map.counts[a * map.elevations + e] / top)));
  });
}

}  // namespace scanplan
