// The keywords of fix insert/* in LIGGGHTS 3.8 order: the general ones (shared by every insert
// style) first, then the style's own. LIGGGHTS stops at the first keyword of the other group, so a
// general keyword after a style keyword is an error ("unknown keyword"). LAMMPS-free.
#pragma once

#include "pack_insertion.h"

#include <string>
#include <vector>

namespace dembridge::insertion {

struct InsertKeywords {
  int seed = 0;
  std::string distribution;
  int maxattempt = 50;
  double nparticles = 0.0, mass = 0.0;  // 0: not given
  bool n_infinite = false;
  double particlerate = 0.0, massrate = 0.0;
  int insert_every = -1;  // -1: not given, 0: once
  long start = -1;        // -1: next step
  bool overlapcheck = true, all_in = false;
  bool exact_number = true;  // random_distribute exact (default) | uncorrelated
  bool verbose = true;
  VelocityRule vel;
  double omega[3] = {0.0, 0.0, 0.0};
  std::string set_property;    // set_property NAME V: the scalar fix property/atom NAME of every new particle
  double set_property_value = 0.0;
};

struct PackKeywords {
  std::string region;
  double volumefraction = 0.0;
  int ntotal = 0;
  double masstotal = 0.0;
  int ntry_mc = 100000;
  bool warn_region = true, check_border = true;
};

struct StreamKeywords {
  std::string face;             // insertion_face: a fix mesh/surface ID
  double extrude_length = 0.0;  // 0: not given
  int duration = 0;             // 0: not given (= insert_every)
  int ntry_mc = 100000;
  bool parallel = false;        // parallel yes: the extrusion depth drawn only where the box is
};

// args[0..2] = ID group style; args[3] must be "seed". Parses seed and the general keywords,
// returns the index of the first keyword that is not one of them. Throws std::invalid_argument.
int parse_general_keywords(const std::vector<std::string> &args, InsertKeywords &k);
// The keywords of insert/pack and insert/rate/region from index i to the end.
void parse_pack_keywords(const std::vector<std::string> &args, int i, PackKeywords &p);
// The keywords of insert/stream from index i to the end.
void parse_stream_keywords(const std::vector<std::string> &args, int i, StreamKeywords &s);
// true for a keyword of parse_general_keywords (to explain a keyword-order error)
bool is_general_keyword(const std::string &key);

}  // namespace dembridge::insertion
