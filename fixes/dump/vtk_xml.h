// The pieces of VTK XML files (ASCII) that the particle and mesh dumps share: the document header, data
// arrays (Float64 with %.17g: the doubles themselves; Float32: the float's exact value with %.17g, as VTK
// writes it; integers), and
// ParaView's .pvd collection. LAMMPS-free.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace dembridge::vtkxml {

// '<?xml ...?>' and the opening VTKFile tag of the given type ("PolyData", "PPolyData", ...).
void header(std::ostream &os, const char *type);

// Text for an XML attribute (array names come from input decks).
std::string escaped(const std::string &s);

// One DataArray element, indented for a Piece: type "Float64", "Float32", "Int32", "Int64" or "UInt8";
// integer types print each value as an integer.
void data_array(std::ostream &os, const char *type, const std::string &name, int components,
                const std::vector<double> &values);
// start, start + step, ... (n values) as an integer array: vertex and polygon lists, cell types.
void counting_array(std::ostream &os, const char *type, const std::string &name, std::size_t n, long long start,
                    long long step);

// A file name's extension ('.vtp'; a dot in a folder name is none) and the name with it replaced.
std::string extension(const std::string &name);
std::string replace_extension(const std::string &name, const std::string &ext);
// 'post/a_*.vtp' -> 'post/a.pvd': the '*' and a separator before it dropped, the extension replaced.
std::string pvd_file(const std::string &pattern);

// ParaView's collection: one DataSet per (file relative to the .pvd's folder, time).
void write_pvd(std::ostream &os, const std::vector<std::pair<std::string, double>> &frames);

}  // namespace dembridge::vtkxml
