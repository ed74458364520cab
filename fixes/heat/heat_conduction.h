// Conduction between touching spheres as LIGGGHTS 3.8's fix heat/gran computes it (contact_area
// overlap): the contact area of two overlapping spheres, the contact conductance and the explicit
// temperature update. LAMMPS-free; the operation order is LIGGGHTS's, so results match bit for bit.
#pragma once

#include <string>

namespace dembridge::heat {

// Area of the circle where two spheres of radii ri, rj at centre distance r intersect.
double overlap_contact_area(double r, double ri, double rj);

// Conductance of a contact: 4 ki kj / (ki + kj) * sqrt(area); 0 if either conductivity is < 1e-5.
double contact_conductance(double ki, double kj, double area);

// The temperature after one step: T + (flux + source) dt / (m c); unchanged if |c| <= 1e-5.
double updated_temperature(double T, double flux, double source, double dt, double mass, double capacity);

// LIGGGHTS 3.8 stores initial_temperature T0 through two text conversions ("%f", then 7 significant
// digits): 300.123456789 becomes 300.1235. Returns the value a LIGGGHTS run starts from.
double liggghts_initial_temperature(double T0);

}  // namespace dembridge::heat
