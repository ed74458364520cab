#include "particle_vtk_xml.h"
#include "vtk_xml.h"

namespace dembridge::vtkout {

namespace {

using vtkxml::data_array;
using vtkxml::extension;
using vtkxml::replace_extension;
using vtkxml::escaped;
using vtkxml::header;

}  // namespace

FileKind file_kind(const std::string &pattern)
{
  const std::string ext = extension(pattern);
  if (ext == ".vtp") return FileKind::PolyData;
  if (ext == ".vtu") return FileKind::UnstructuredGrid;
  if (ext == ".pvtp") return FileKind::ParallelPolyData;
  if (ext == ".pvtu") return FileKind::ParallelUnstructuredGrid;
  return FileKind::Legacy;
}

std::optional<std::string> unwritten_xml_extension(const std::string &pattern)
{
  const std::string ext = extension(pattern);
  for (const char *e : {".vtm", ".vti", ".vtr", ".pvti", ".pvtr"})
    if (ext == e) return ext;
  return std::nullopt;
}

bool is_parallel(FileKind k)
{
  return k == FileKind::ParallelPolyData || k == FileKind::ParallelUnstructuredGrid;
}

bool is_unstructured(FileKind k)
{
  return k == FileKind::UnstructuredGrid || k == FileKind::ParallelUnstructuredGrid;
}

void write_xml_particles(std::ostream &os, const ParticleFrame &frame, bool unstructured)
{
  const std::size_t n = frame.xyz.size() / 3;
  const char *kind = unstructured ? "UnstructuredGrid" : "PolyData";
  header(os, kind);
  os << "  <" << kind << ">\n    <Piece NumberOfPoints=\"" << n << '"';
  if (unstructured) os << " NumberOfCells=\"" << n << "\">\n";
  else os << " NumberOfVerts=\"" << n << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  os << "      <PointData>\n";
  for (const ParticleArray &a : frame.arrays) data_array(os, a.integer ? "Int32" : "Float64", a.name, a.components, a.values);
  os << "      </PointData>\n      <CellData>\n      </CellData>\n      <Points>\n";
  data_array(os, "Float32", "Points", 3, frame.xyz);
  os << "      </Points>\n      <" << (unstructured ? "Cells" : "Verts") << ">\n";
  // One vertex cell per particle: connectivity k, offsets k + 1 (and VTK_VERTEX = 1 as each cell's type).
  vtkxml::counting_array(os, "Int64", "connectivity", n, 0, 1);
  vtkxml::counting_array(os, "Int64", "offsets", n, 1, 1);
  if (unstructured) vtkxml::counting_array(os, "UInt8", "types", n, 1, 0);
  os << "      </" << (unstructured ? "Cells" : "Verts") << ">\n    </Piece>\n  </" << kind << ">\n</VTKFile>\n";
}

void write_xml_parallel_particles(std::ostream &os, const ParticleFrame &frame, bool unstructured,
                                  const std::string &piece)
{
  const char *kind = unstructured ? "PUnstructuredGrid" : "PPolyData";
  header(os, kind);
  os << "  <" << kind << " GhostLevel=\"0\">\n    <PPointData>\n";
  for (const ParticleArray &a : frame.arrays) {
    os << "      <PDataArray type=\"" << (a.integer ? "Int32" : "Float64") << "\" Name=\"" << escaped(a.name) << '"';
    if (a.components != 1) os << " NumberOfComponents=\"" << a.components << '"';
    os << "/>\n";
  }
  os << "    </PPointData>\n    <PPoints>\n      <PDataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\"/>\n"
     << "    </PPoints>\n    <Piece Source=\"" << escaped(piece) << "\"/>\n  </" << kind << ">\n</VTKFile>\n";
}

void write_xml_bounding_box(std::ostream &os, const double lo[3], const double hi[3])
{
  header(os, "RectilinearGrid");
  os << "  <RectilinearGrid WholeExtent=\"0 1 0 1 0 1\">\n    <Piece Extent=\"0 1 0 1 0 1\">\n"
     << "      <PointData>\n      </PointData>\n      <CellData>\n      </CellData>\n      <Coordinates>\n";
  const char *axis[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d) data_array(os, "Float64", axis[d], 1, {lo[d], hi[d]});
  os << "      </Coordinates>\n    </Piece>\n  </RectilinearGrid>\n</VTKFile>\n";
}

void write_xml_parallel_bounding_box(std::ostream &os, const std::string &piece)
{
  header(os, "PRectilinearGrid");
  os << "  <PRectilinearGrid WholeExtent=\"0 1 0 1 0 1\" GhostLevel=\"0\">\n    <PPointData>\n    </PPointData>\n"
     << "    <PCoordinates>\n";
  for (const char *axis : {"x", "y", "z"}) os << "      <PDataArray type=\"Float64\" Name=\"" << axis << "\"/>\n";
  os << "    </PCoordinates>\n    <Piece Extent=\"0 1 0 1 0 1\" Source=\"" << escaped(piece)
     << "\"/>\n  </PRectilinearGrid>\n</VTKFile>\n";
}

std::string xml_bounding_box_file(const std::string &pattern, long long step)
{
  return replace_extension(bounding_box_file(pattern, step), is_parallel(file_kind(pattern)) ? ".pvtr" : ".vtr");
}

std::string piece_file(const std::string &parallel_file)
{
  const std::string ext = extension(parallel_file);  // ".pvtp" -> "_0.vtp"
  return parallel_file.substr(0, parallel_file.size() - ext.size()) + "_0." + ext.substr(2);
}

}  // namespace dembridge::vtkout
