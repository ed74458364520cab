#include "file_text.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "protocol_error.h"

namespace dembridge::mbdyn {

namespace {

// The data lines of text (comments `#...` and blank lines left out), each split into words,
// with their 1-based line numbers.
struct Line {
  int number;
  std::vector<std::string> words;
};

std::vector<Line> data_lines(const std::string& text) {
  std::vector<Line> out;
  std::istringstream in(text);
  std::string s;
  int number = 0;
  while (std::getline(in, s)) {
    ++number;
    std::istringstream words(s);
    Line l{number, {}};
    for (std::string w; words >> w;) l.words.push_back(w);
    if (!l.words.empty() && l.words[0][0] != '#') out.push_back(l);
  }
  return out;
}

double number_at(const Line& l, std::size_t i, const std::string& what, const char* field) {
  const std::string& w = l.words[i];
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(w.c_str(), &end);
  if (*end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw MalformedMessageError(what + " line " + std::to_string(l.number) + ": " + field + " expects a finite number, got '" +
                                w + "'");
  return v;
}

std::uint32_t label_at(const Line& l, const std::string& what) {
  const std::string& w = l.words[0];
  char* end = nullptr;
  errno = 0;
  const unsigned long v = std::strtoul(w.c_str(), &end, 10);
  if (w[0] == '-' || *end != '\0' || errno == ERANGE || v > 0xFFFFFFFFul)
    throw MalformedMessageError(what + " line " + std::to_string(l.number) + ": expected a label (an integer), got '" + w +
                                "'");
  return static_cast<std::uint32_t>(v);
}

// Checks the line count and every line's word count.
void require_shape(const std::vector<Line>& lines, std::size_t n, std::size_t words, const std::string& what,
                   const char* layout) {
  if (lines.size() != n)
    throw MalformedMessageError(what + ": expected " + std::to_string(n) + " point line(s) (" + layout + "), found " +
                                std::to_string(lines.size()));
  for (const Line& l : lines)
    if (l.words.size() != words)
      throw MalformedMessageError(what + " line " + std::to_string(l.number) + ": expected " + std::to_string(words) +
                                  " values (" + layout + "), found " + std::to_string(l.words.size()));
}

void require_no_reference(const NodalConfig& config) {
  if (config.reference_node)
    throw std::invalid_argument("the file communicator is supported without reference node only");
}

void append(std::string& out, const double* v, std::size_t n, int precision) {
  char buf[64];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(buf, sizeof(buf), " %.*e", precision, v[i]);
    out += buf;
  }
}

void append_label(std::string& out, bool labels, std::uint32_t label) {
  if (labels) out += std::to_string(label);
}

// Removes the leading blank the first value of a line got when there is no label.
void end_line(std::string& out, std::size_t start) {
  if (out.size() > start && out[start] == ' ') out.erase(start, 1);
  out += '\n';
}

std::string layout_of_out(const NodalConfig& c) {
  std::string s = c.labels ? "label x y z" : "x y z";
  switch (c.rotation) {
    case Rotation::OrientationMatrix: s += " R11..R33"; break;
    case Rotation::OrientationVector: s += " theta(3)"; break;
    case Rotation::Euler123: s += " euler123(3)"; break;
    case Rotation::None: break;
  }
  s += c.has_rotation() ? " v(3) w(3)" : " v(3)";
  if (c.accelerations) s += c.has_rotation() ? " a(3) wdot(3)" : " a(3)";
  return s;
}

}  // namespace

void parse_kinematics_text(const NodalConfig& config, const std::string& text, const std::string& what, Kinematics& k) {
  require_no_reference(config);
  std::vector<WireSpan> spans;
  kinematics_wire_spans(config, k, spans);  // shapes k
  k.command = Command::RegularDataAndGotoNextStep;
  const std::size_t n = config.num_points, nr = config.rotation_doubles();
  const bool rot = config.has_rotation(), acc = config.accelerations;
  const std::size_t words = (config.labels ? 1 : 0) + config.point_kinematics_doubles();
  const std::vector<Line> lines = data_lines(text);
  const std::string layout = layout_of_out(config);
  require_shape(lines, n, words, what, layout.c_str());
  for (std::size_t i = 0; i < n; ++i) {
    const Line& l = lines[i];
    std::size_t w = 0;
    if (config.labels) k.labels[i] = label_at(l, what), ++w;
    auto take = [&](double* dst, std::size_t count, const char* field) {
      for (std::size_t j = 0; j < count; ++j) dst[j] = number_at(l, w++, what, field);
    };
    take(&k.x[3 * i], 3, "x");
    if (config.rotation == Rotation::OrientationMatrix) {
      double r[9];  // row by row in the file, column-major in a Kinematics (the wire's order)
      take(r, 9, "R");
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) k.orientation[9 * i + 3 * col + row] = r[3 * row + col];
    } else if (rot) {
      take(&k.orientation[nr * i], nr, "orientation");
    }
    take(&k.v[3 * i], 3, "v");
    if (rot) take(&k.omega[3 * i], 3, "w");
    if (acc) take(&k.a[3 * i], 3, "a");
    if (acc && rot) take(&k.omega_dot[3 * i], 3, "wdot");
  }
}

std::string format_kinematics_text(const NodalConfig& config, const Kinematics& k, int precision) {
  require_no_reference(config);
  std::string out = "# regular nodes\n";
  const std::size_t nr = config.rotation_doubles();
  const bool rot = config.has_rotation(), acc = config.accelerations;
  for (std::size_t i = 0; i < config.num_points; ++i) {
    const std::size_t start = out.size();
    append_label(out, config.labels, config.labels ? k.labels[i] : 0);
    append(out, &k.x[3 * i], 3, precision);
    if (config.rotation == Rotation::OrientationMatrix) {
      const Matrix3 R = matrix_from_wire_column_major(&k.orientation[9 * i]);
      append(out, R.data(), 9, precision);
    } else if (rot) {
      append(out, &k.orientation[nr * i], nr, precision);
    }
    append(out, &k.v[3 * i], 3, precision);
    if (rot) append(out, &k.omega[3 * i], 3, precision);
    if (acc) append(out, &k.a[3 * i], 3, precision);
    if (acc && rot) append(out, &k.omega_dot[3 * i], 3, precision);
    end_line(out, start);
  }
  return out;
}

std::string format_loads_text(const NodalConfig& config, const Loads& loads, const std::vector<std::uint32_t>& labels,
                              int precision) {
  require_no_reference(config);
  std::string out;
  for (std::size_t i = 0; i < config.num_points; ++i) {
    const std::size_t start = out.size();
    append_label(out, config.labels, config.labels ? labels.at(i) : 0);
    append(out, &loads.force[3 * i], 3, precision);
    if (config.has_rotation()) append(out, &loads.moment[3 * i], 3, precision);
    end_line(out, start);
  }
  return out;
}

Loads parse_loads_text(const NodalConfig& config, const std::string& text, const std::string& what) {
  require_no_reference(config);
  Loads l(config);
  const bool rot = config.has_rotation();
  const std::size_t words = (config.labels ? 1 : 0) + (rot ? 6 : 3);
  const std::vector<Line> lines = data_lines(text);
  const char* layout = config.labels ? (rot ? "label Fx Fy Fz Mx My Mz" : "label Fx Fy Fz")
                                     : (rot ? "Fx Fy Fz Mx My Mz" : "Fx Fy Fz");
  require_shape(lines, config.num_points, words, what, layout);
  if (config.labels) l.labels.resize(config.num_points);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::size_t w = 0;
    if (config.labels) l.labels[i] = label_at(lines[i], what), ++w;
    for (int c = 0; c < 3; ++c) l.force[3 * i + c] = number_at(lines[i], w++, what, "F");
    for (int c = 0; c < 3 && rot; ++c) l.moment[3 * i + c] = number_at(lines[i], w++, what, "M");
  }
  return l;
}

}  // namespace dembridge::mbdyn
