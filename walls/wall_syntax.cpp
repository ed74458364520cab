#include "wall_syntax.h"
#include "math/number_word.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <set>

namespace dembridge::walls {

using gran::SyntaxError;

namespace {

const std::set<std::string> &legacy_names()
{
  static const std::set<std::string> s = {"wall/gran/hooke", "wall/gran/hooke/history", "wall/gran/hertz/history",
                                          "wall/gran/hooke/stiffness", "wall/gran/hooke/history/stiffness",
                                          "wall/gran/hertz/history/stiffness"};
  return s;
}

// Words that end the contact-model part of a 3.x line (spec §1.1).
bool is_wall_keyword(const std::string &w)
{
  static const std::set<std::string> s = {"primitive", "mesh", "n_meshes", "meshes", "shear", "store_force",
                                          "store_force_contact", "store_force_contact_every", "track_energy",
                                          "temperature", "contact_area"};
  return s.count(w) > 0;
}

// 2.x model keywords that may appear anywhere among the wall keywords.
bool is_2x_model_keyword(const std::string &w)
{
  return w == "rolling_friction" || w == "cohesion" || w == "tangential_damping" || w == "viscous" || w == "absolute_damping";
}

double number(const std::string &prefix, const std::string &what, const std::vector<std::string> &a, std::size_t k)
{
  if (k >= a.size()) throw SyntaxError(prefix + ": missing " + what + " at the end of the line");
  double v;
  if (!math::read_number(a[k], v)) throw SyntaxError(prefix + ": expected a number for " + what + ", got '" + a[k] + "'");
  return v;
}

int integer(const std::string &prefix, const std::string &what, const std::vector<std::string> &a, std::size_t k)
{
  if (k >= a.size()) throw SyntaxError(prefix + ": missing " + what + " at the end of the line");
  long long v;
  if (!math::read_integer(a[k], v) || v > INT_MAX || v < INT_MIN)
    throw SyntaxError(prefix + ": expected an integer for " + what + ", got '" + a[k] + "'");
  return int(v);
}

// Re-labels a pair-style syntax error as this fix's.
SyntaxError relabel(const SyntaxError &e, const std::string &pair_prefix, const std::string &prefix)
{
  std::string m = e.what();
  if (m.compare(0, pair_prefix.size(), pair_prefix) == 0) m = prefix + m.substr(pair_prefix.size());
  return SyntaxError(m);
}

// Parses the wall keywords from args[k]; model keywords of the 2.x syntax go to model_args.
void parse_wall_keywords(const std::vector<std::string> &a, std::size_t k, const std::string &prefix, bool legacy, WallSpec &s,
                         std::vector<std::string> &model_args)
{
  bool have_primitive = false, have_mesh = false;
  int n_meshes = -1;
  while (k < a.size()) {
    const std::string &w = a[k];
    if (w == "primitive") {
      if (have_mesh || have_primitive)
        throw SyntaxError(prefix + ": 'primitive' given together with " + std::string(have_mesh ? "'mesh'" : "another 'primitive'") +
                          " in one fix (LIGGGHTS silently ignored one of them); use one fix wall/gran per wall");
      have_primitive = true;
      if (k + 1 >= a.size() || a[k + 1] != "type")
        throw SyntaxError(prefix + ": expected 'type' after 'primitive' (primitive type T xplane|yplane|zplane POS or x/y/zcylinder R C1 C2)");
      s.primitive.wall_type = integer(prefix, "the primitive wall type", a, k + 2);
      if (k + 3 >= a.size()) throw SyntaxError(prefix + ": missing the primitive shape after 'primitive type T'");
      const std::string &shape = a[k + 3];
      const bool plane = shape == "xplane" || shape == "yplane" || shape == "zplane";
      const bool cyl = shape == "xcylinder" || shape == "ycylinder" || shape == "zcylinder";
      if (!plane && !cyl)
        throw SyntaxError(prefix + ": unknown primitive wall '" + shape +
                          "', expected xplane, yplane, zplane, xcylinder, ycylinder or zcylinder");
      s.primitive.axis = shape[0] - 'x';
      if (plane) {
        s.primitive.shape = PrimitiveWall::Shape::Plane;
        s.primitive.pos = number(prefix, "the position of the " + shape, a, k + 4);
        k += 5;
      } else {
        s.primitive.shape = PrimitiveWall::Shape::Cylinder;
        s.primitive.radius = number(prefix, "the radius of the " + shape, a, k + 4);
        s.primitive.c1 = number(prefix, "the first axis coordinate of the " + shape, a, k + 5);
        s.primitive.c2 = number(prefix, "the second axis coordinate of the " + shape, a, k + 6);
        if (!(s.primitive.radius > 0.0))
          throw SyntaxError(prefix + ": the radius of the " + shape + " must be > 0, got '" + a[k + 4] + "'");
        k += 7;
      }
    } else if (w == "mesh") {
      if (have_primitive || have_mesh)
        throw SyntaxError(prefix + ": 'mesh' given together with " + std::string(have_primitive ? "'primitive'" : "another 'mesh'") +
                          " in one fix (LIGGGHTS silently ignored one of them); use one fix wall/gran per wall");
      have_mesh = true;
      s.is_mesh = true;
      k += 1;
    } else if (w == "n_meshes") {
      if (!have_mesh) throw SyntaxError(prefix + ": 'n_meshes' is only valid after 'mesh'");
      n_meshes = integer(prefix, "n_meshes", a, k + 1);
      if (n_meshes < 1) throw SyntaxError(prefix + ": n_meshes must be >= 1, got '" + a[k + 1] + "'");
      k += 2;
    } else if (w == "meshes") {
      if (!have_mesh) throw SyntaxError(prefix + ": 'meshes' is only valid after 'mesh'");
      if (n_meshes < 0) throw SyntaxError(prefix + ": have to define 'n_meshes' before 'meshes'");
      for (int m = 0; m < n_meshes; ++m) {
        if (k + 1 + m >= a.size() || is_wall_keyword(a[k + 1 + m]) || is_2x_model_keyword(a[k + 1 + m]))
          throw SyntaxError(prefix + ": 'meshes' expects " + std::to_string(n_meshes) + " mesh fix IDs (n_meshes), got " +
                            std::to_string(m));
        const std::string &id = a[k + 1 + m];
        if (std::find(s.mesh_ids.begin(), s.mesh_ids.end(), id) != s.mesh_ids.end())
          throw SyntaxError(prefix + ": mesh '" + id + "' is listed twice in 'meshes' (expected " + std::to_string(n_meshes) +
                            " different mesh fix IDs; a repeated mesh would act twice and double its wall force)");
        s.mesh_ids.push_back(id);
      }
      k += 1 + n_meshes;
    } else if (w == "shear") {
      if (k + 2 >= a.size()) throw SyntaxError(prefix + ": 'shear' expects a dimension x|y|z and a velocity");
      const std::string &d = a[k + 1];
      if (d != "x" && d != "y" && d != "z") throw SyntaxError(prefix + ": 'shear' expects x, y or z, got '" + d + "'");
      s.shear_dim = d[0] - 'x';
      s.shear_v = number(prefix, "the shear velocity", a, k + 2);
      k += 3;
    } else if (w == "store_force") {
      if (k + 1 >= a.size() || (a[k + 1] != "yes" && a[k + 1] != "no"))
        throw SyntaxError(prefix + ": 'store_force' expects yes or no");
      if (a[k + 1] == "yes")
        throw SyntaxError(prefix + ": 'store_force yes' is not supported by dembridge (use compute wall/gran/local for per-contact forces)");
      k += 2;
    } else if (legacy && is_2x_model_keyword(w)) {
      if (k + 1 >= a.size()) throw SyntaxError(prefix + ": keyword '" + w + "' needs a value");
      model_args.push_back(w);
      model_args.push_back(a[k + 1]);
      k += 2;
    } else if (is_wall_keyword(w)) {
      throw SyntaxError(prefix + ": keyword '" + w + "' is not supported by dembridge");
    } else {
      throw SyntaxError(prefix + ": unknown argument or wrong keyword order: '" + w +
                        "' (expected primitive type T ..., mesh n_meshes N meshes ..., shear, store_force)");
    }
  }
  if (!have_primitive && !have_mesh)
    throw SyntaxError(prefix + ": no wall given; expected 'primitive type T xplane|...' or 'mesh n_meshes N meshes ID ...'");
  if (have_mesh && s.mesh_ids.empty())
    throw SyntaxError(prefix + ": 'mesh' needs 'n_meshes N meshes ID1 ... IDN'");
  if (have_mesh && s.shear_dim >= 0) throw SyntaxError(prefix + ": 'shear' is only available for primitive walls");
}

}  // namespace

bool is_liggghts_wall_style(const std::string &style) { return style == "wall/gran" || legacy_names().count(style) > 0; }

bool is_lammps_wall_syntax(const std::string &style, const std::vector<std::string> &args)
{
  if (style != "wall/gran" || args.empty()) return false;
  const std::string &a = args[0];
  return a == "hooke" || a == "hooke/history" || a == "hertz/history" || a == "granular";
}

WallSpec parse_wall_gran(const std::string &style, const std::vector<std::string> &args, const std::string &prefix)
{
  WallSpec s;
  std::vector<std::string> model_args;
  if (style == "wall/gran") {
    if (args.empty() || args[0] != "model")
      throw SyntaxError(prefix + ": expected 'model hooke|hertz|hooke/stiffness|hertz/stiffness' as first argument");
    std::size_t k = 0;
    while (k < args.size() && !is_wall_keyword(args[k])) model_args.push_back(args[k++]);
    try {
      s.model = gran::parse_pair_style("gran", model_args);
    } catch (const SyntaxError &e) {
      throw relabel(e, "pair_style gran", prefix);
    }
    parse_wall_keywords(args, k, prefix, false, s, model_args);
  } else {
    if (!legacy_names().count(style)) throw SyntaxError(prefix + ": unknown wall style '" + style + "'");
    parse_wall_keywords(args, 0, prefix, true, s, model_args);
    const std::string pair_style = style.substr(5);  // wall/gran/X -> gran/X
    try {
      s.model = gran::parse_pair_style(pair_style, model_args);
    } catch (const SyntaxError &e) {
      throw relabel(e, "pair_style " + pair_style, prefix);
    }
  }
  s.model.style = style;
  return s;
}

}  // namespace dembridge::walls
