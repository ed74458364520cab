// Particle output in LIGGGHTS 3.8's dump custom/vtk layout (legacy VTK 5.1 POLYDATA, ASCII): one
// vertex per particle, the per-particle arrays as FIELD data, a bounding-box file beside each frame
// (RECTILINEAR_GRID) and a ParaView series file listing every frame with its time. LAMMPS-free.
#pragma once

#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dembridge::vtkout {

struct ParticleArray {
  std::string name;            // LIGGGHTS's array name (e.g. "v", "radius", "f_Temp[0]")
  int components = 1;          // 1 or 3
  bool integer = false;        // written as int (id, type, image flags)
  std::vector<double> values;  // components values per particle, particle after particle
};

struct ParticleFrame {
  std::vector<double> xyz;  // 3 per particle
  std::vector<ParticleArray> arrays;
};

// Points as float (VTK's 'float' type, as LIGGGHTS writes them; %.9g round-trips a float), doubles
// with %.17g (round-trips a double), ints with %d; nine values a line as VTK's legacy writer.
void write_polydata(std::ostream &os, const ParticleFrame &frame, const std::string &title);

void write_bounding_box(std::ostream &os, const double lo[3], const double hi[3], const std::string &title);

// ParaView's file-series JSON ("NAME.vtk.series"): ParaView's .pvd reader takes XML files only,
// while a .series file groups legacy .vtk files with their times.
void write_series(std::ostream &os, const std::vector<std::pair<std::string, double>> &frames);

// 'post/a_*.vtk' at step 200 -> 'post/a_200.vtk' (no '*': the name itself, overwritten each frame).
std::string frame_file(const std::string &pattern, long long step);
// LIGGGHTS 3.8's names: 'post/a_*.vtk' -> 'post/a_boundingBox_200.vtk', 'post/a.vtk' -> 'post/a_boundingBox.vtk'.
std::string bounding_box_file(const std::string &pattern, long long step);
// 'post/a_*.vtk' -> 'post/a.vtk.series' (the '*' and a separator before it dropped).
std::string series_file(const std::string &pattern);
// The file name without its folder, as a series file in that folder refers to it.
std::string base_name(const std::string &path);

}  // namespace dembridge::vtkout
