#include "oracle_data.h"

#include <zlib.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace oracle {

std::string dir(const std::string& relative) { return std::string(DEMBRIDGE_PARMEC_ORACLE_DIR) + "/" + relative; }

namespace {

bool exists(const std::string& p) { return std::ifstream(p).good(); }

std::string slurp(const std::string& path) {
  std::string p = path;
  if (!exists(p) && exists(p + ".gz")) p += ".gz";
  gzFile f = gzopen(p.c_str(), "rb");  // also reads uncompressed files transparently
  if (!f) throw std::runtime_error("oracle file not found: " + path);
  std::string out;
  char buf[1 << 16];
  int n;
  while ((n = gzread(f, buf, sizeof buf)) > 0) out.append(buf, n);
  gzclose(f);
  return out;
}

}  // namespace

const std::vector<double>& History::operator[](const std::string& name) const {
  auto it = cols.find(name);
  if (it == cols.end()) throw std::runtime_error("oracle column missing: " + name);
  return it->second;
}

History read_history(const std::string& path) {
  const std::string text = slurp(path);
  History h;
  std::size_t pos = text.find('\n');
  {
    std::stringstream hs(text.substr(0, pos));
    std::string name;
    while (std::getline(hs, name, ',')) h.names.push_back(name);
  }
  std::vector<std::vector<double>*> col;
  for (const auto& n : h.names) col.push_back(&h.cols[n]);
  const char* c = text.c_str() + pos + 1;
  const char* end = text.c_str() + text.size();
  while (c < end) {
    for (std::size_t i = 0; i < col.size(); ++i) {
      char* next;
      col[i]->push_back(std::strtod(c, &next));
      c = next + 1;  // skip ',' or '\n'
    }
    while (c < end && (*c == '\n' || *c == '\r')) ++c;
  }
  return h;
}

std::vector<double> meta_numbers(const std::string& json_path, const std::string& key) {
  const std::string text = slurp(json_path);
  std::size_t p = text.find("\"" + key + "\"");
  if (p == std::string::npos) throw std::runtime_error("meta key missing: " + key + " in " + json_path);
  p = text.find(':', p) + 1;
  std::vector<double> out;
  int depth = 0;
  while (p < text.size()) {
    const char ch = text[p];
    if (ch == '[') {
      ++depth;
      ++p;
    } else if (ch == ']') {
      --depth;
      ++p;
      if (depth == 0) break;
    } else if (ch == ',' || std::isspace(static_cast<unsigned char>(ch))) {
      if (depth == 0 && ch == ',') break;
      ++p;
    } else if (text.compare(p, 3, "NaN") == 0) {
      out.push_back(std::numeric_limits<double>::quiet_NaN());
      p += 3;
    } else if (text.compare(p, 8, "Infinity") == 0) {
      out.push_back(std::numeric_limits<double>::infinity());
      p += 8;
    } else if (text.compare(p, 9, "-Infinity") == 0) {
      out.push_back(-std::numeric_limits<double>::infinity());
      p += 9;
    } else {
      char* next;
      const double v = std::strtod(text.c_str() + p, &next);
      if (next == text.c_str() + p) break;  // not a number (object): stop
      out.push_back(v);
      p = next - text.c_str();
    }
    if (depth == 0 && !out.empty()) break;
  }
  return out;
}

double meta_number(const std::string& json_path, const std::string& key) {
  const auto v = meta_numbers(json_path, key);
  if (v.empty()) throw std::runtime_error("meta key has no number: " + key);
  return v.front();
}

}  // namespace oracle
