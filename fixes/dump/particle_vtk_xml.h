// Particle output as VTK XML files (ASCII), the layout LIGGGHTS 3.8's dump custom/vtk writes when the file
// name ends in .vtp (PolyData), .vtu (UnstructuredGrid), .pvtp or .pvtu (a parallel header naming its
// piece files), with an XML bounding-box file (.vtr, or .pvtr and its piece); the dump adds the .pvd
// (vtk_xml.h). LAMMPS-free; the frame is the legacy writer's.
#pragma once

#include "particle_vtk.h"
#include "vtk_xml.h"

#include <optional>
#include <ostream>
#include <string>

namespace dembridge::vtkout {

enum class FileKind { Legacy, PolyData, UnstructuredGrid, ParallelPolyData, ParallelUnstructuredGrid };

// By the name's extension, as LIGGGHTS 3.8 reads it: .vtp .vtu .pvtp .pvtu; .vtk and any other: Legacy.
FileKind file_kind(const std::string &pattern);
// The VTK XML extensions dump custom/vtk does not write (.vtm .vti .vtr .pvti .pvtr): the one found, or none.
std::optional<std::string> unwritten_xml_extension(const std::string &pattern);

bool is_parallel(FileKind k);
bool is_unstructured(FileKind k);

// One serial XML file: the particles as vertices, the arrays as point data (Int32 / Float64 with %.17g),
// the points as Float32, as LIGGGHTS (VTK's float points).
void write_xml_particles(std::ostream &os, const ParticleFrame &frame, bool unstructured);
// The parallel header (.pvtp / .pvtu): the arrays' names and types, and the piece file it names.
void write_xml_parallel_particles(std::ostream &os, const ParticleFrame &frame, bool unstructured,
                                  const std::string &piece);
// The box as a 2x2x2 RectilinearGrid (.vtr) and its parallel header (.pvtr) naming that piece.
void write_xml_bounding_box(std::ostream &os, const double lo[3], const double hi[3]);
void write_xml_parallel_bounding_box(std::ostream &os, const std::string &piece);

// The XML bounding box beside a frame: 'post/a_*.vtp' -> 'post/a_boundingBox_200.vtr' ('.pvtr' for .pvtp/.pvtu).
std::string xml_bounding_box_file(const std::string &pattern, long long step);
// A parallel file's one piece, as LIGGGHTS 3.8 names rank 0's: 'post/d_200.pvtp' -> 'post/d_200_0.vtp'.
std::string piece_file(const std::string &parallel_file);

}  // namespace dembridge::vtkout
