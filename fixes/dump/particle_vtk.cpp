#include "particle_vtk.h"

#include <cstdio>

namespace dembridge::vtkout {

namespace {

constexpr int kPerLine = 9;  // vtkDataWriter's ASCII line length in values

template <class Fmt> void write_values(std::ostream &os, std::size_t n, Fmt &&fmt)
{
  char buf[40];
  for (std::size_t k = 0; k < n; ++k) {
    fmt(buf, sizeof buf, k);
    os << buf << ' ';
    if ((k + 1) % kPerLine == 0 && k + 1 < n) os << '\n';
  }
  os << '\n';
}

void write_doubles(std::ostream &os, const std::vector<double> &v)
{
  write_values(os, v.size(), [&](char *b, std::size_t s, std::size_t k) { std::snprintf(b, s, "%.17g", v[k]); });
}

std::string replace_star(const std::string &pattern, const std::string &by)
{
  const auto star = pattern.find('*');
  if (star == std::string::npos) return pattern;
  return pattern.substr(0, star) + by + pattern.substr(star + 1);
}

}  // namespace

void write_polydata(std::ostream &os, const ParticleFrame &frame, const std::string &title)
{
  const std::size_t n = frame.xyz.size() / 3;
  os << "# vtk DataFile Version 5.1\n" << title << "\nASCII\nDATASET POLYDATA\n";
  os << "POINTS " << n << " float\n";
  write_values(os, frame.xyz.size(), [&](char *b, std::size_t s, std::size_t k) {
    std::snprintf(b, s, "%.9g", static_cast<double>(static_cast<float>(frame.xyz[k])));
  });
  os << "VERTICES " << n + 1 << ' ' << n << "\nOFFSETS vtktypeint64\n";
  write_values(os, n + 1, [](char *b, std::size_t s, std::size_t k) { std::snprintf(b, s, "%zu", k); });
  os << "CONNECTIVITY vtktypeint64\n";
  write_values(os, n, [](char *b, std::size_t s, std::size_t k) { std::snprintf(b, s, "%zu", k); });
  os << "POINT_DATA " << n << "\nFIELD FieldData " << frame.arrays.size() << '\n';
  for (const ParticleArray &a : frame.arrays) {
    os << a.name << ' ' << a.components << ' ' << n << (a.integer ? " int\n" : " double\n");
    if (a.integer)
      write_values(os, a.values.size(), [&](char *b, std::size_t s, std::size_t k) {
        std::snprintf(b, s, "%d", static_cast<int>(a.values[k]));
      });
    else write_doubles(os, a.values);
  }
}

void write_bounding_box(std::ostream &os, const double lo[3], const double hi[3], const std::string &title)
{
  os << "# vtk DataFile Version 5.1\n" << title << "\nASCII\nDATASET RECTILINEAR_GRID\nDIMENSIONS 2 2 2\n";
  const char *axis[3] = {"X", "Y", "Z"};
  for (int d = 0; d < 3; ++d) {
    os << axis[d] << "_COORDINATES 2 double\n";
    write_doubles(os, {lo[d], hi[d]});
  }
}

void write_series(std::ostream &os, const std::vector<std::pair<std::string, double>> &frames)
{
  os << "{\n  \"file-series-version\" : \"1.0\",\n  \"files\" : [\n";
  char t[40];
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::snprintf(t, sizeof t, "%.17g", frames[k].second);
    os << "    { \"name\" : \"" << frames[k].first << "\", \"time\" : " << t << " }"
       << (k + 1 < frames.size() ? ",\n" : "\n");
  }
  os << "  ]\n}\n";
}

std::string frame_file(const std::string &pattern, long long step)
{
  return replace_star(pattern, std::to_string(step));
}

std::string bounding_box_file(const std::string &pattern, long long step)
{
  if (pattern.find('*') != std::string::npos) return replace_star(pattern, "boundingBox_" + std::to_string(step));
  const auto dot = pattern.rfind('.');
  const auto slash = pattern.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return pattern + "_boundingBox";
  return pattern.substr(0, dot) + "_boundingBox" + pattern.substr(dot);
}

std::string series_file(const std::string &pattern)
{
  std::string s = pattern;
  const auto star = s.find('*');
  if (star != std::string::npos) {
    std::size_t from = star;
    if (from > 0 && (s[from - 1] == '_' || s[from - 1] == '-' || s[from - 1] == '.')) --from;
    s.erase(from, star + 1 - from);
  }
  return s + ".series";
}

std::string base_name(const std::string &path)
{
  const auto slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

}  // namespace dembridge::vtkout
