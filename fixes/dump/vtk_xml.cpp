#include "vtk_xml.h"

#include <cstdio>
#include <cstring>

namespace dembridge::vtkxml {

namespace {

constexpr int kPerLine = 9;

template <class Fmt> void values(std::ostream &os, std::size_t n, Fmt &&fmt)
{
  char buf[40];
  for (std::size_t k = 0; k < n; ++k) {
    if (k % kPerLine == 0) os << (k ? "\n" : "") << "          ";
    else os << ' ';
    fmt(buf, sizeof buf, k);
    os << buf;
  }
  if (n) os << '\n';
}

void open_array(std::ostream &os, const char *type, const std::string &name, int components)
{
  os << "        <DataArray type=\"" << type << "\" Name=\"" << escaped(name) << '"';
  if (components != 1) os << " NumberOfComponents=\"" << components << '"';
  os << " format=\"ascii\">\n";
}

}  // namespace

void header(std::ostream &os, const char *type)
{
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
     << "\" version=\"0.1\" byte_order=\"LittleEndian\" header_type=\"UInt32\">\n";
}

std::string escaped(const std::string &s)
{
  std::string out;
  for (char c : s) {
    if (c == '&') out += "&amp;";
    else if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

void data_array(std::ostream &os, const char *type, const std::string &name, int components,
                const std::vector<double> &v)
{
  open_array(os, type, name, components);
  if (std::strcmp(type, "Float64") == 0)
    values(os, v.size(), [&](char *b, std::size_t s, std::size_t k) { std::snprintf(b, s, "%.17g", v[k]); });
  else if (std::strcmp(type, "Float32") == 0)
    values(os, v.size(), [&](char *b, std::size_t s, std::size_t k) {
      std::snprintf(b, s, "%.17g", static_cast<double>(static_cast<float>(v[k])));
    });
  else
    values(os, v.size(), [&](char *b, std::size_t s, std::size_t k) {
      std::snprintf(b, s, "%lld", static_cast<long long>(v[k]));
    });
  os << "        </DataArray>\n";
}

void counting_array(std::ostream &os, const char *type, const std::string &name, std::size_t n, long long start,
                    long long step)
{
  open_array(os, type, name, 1);
  values(os, n, [&](char *b, std::size_t s, std::size_t k) {
    std::snprintf(b, s, "%lld", start + step * static_cast<long long>(k));
  });
  os << "        </DataArray>\n";
}

std::string extension(const std::string &name)
{
  const auto dot = name.rfind('.');
  const auto slash = name.rfind('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return name.substr(dot);
}

std::string replace_extension(const std::string &name, const std::string &ext)
{
  return name.substr(0, name.size() - extension(name).size()) + ext;
}

std::string pvd_file(const std::string &pattern)
{
  std::string s = pattern;
  const auto star = s.find('*');
  if (star != std::string::npos) {
    std::size_t from = star;
    if (from > 0 && (s[from - 1] == '_' || s[from - 1] == '-' || s[from - 1] == '.')) --from;
    s.erase(from, star + 1 - from);
  }
  return replace_extension(s, ".pvd");
}

void write_pvd(std::ostream &os, const std::vector<std::pair<std::string, double>> &frames)
{
  os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
     << "  <Collection>\n";
  char t[40];
  for (const auto &f : frames) {
    std::snprintf(t, sizeof t, "%.17g", f.second);
    os << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << escaped(f.first) << "\"/>\n";
  }
  os << "  </Collection>\n</VTKFile>\n";
}

}  // namespace dembridge::vtkxml
