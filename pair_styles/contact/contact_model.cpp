// ContactLaw is header-only for inlining into the neighbour loop; this unit keeps the library
// non-empty and checks that the headers compile on their own.
#include "contact_law.h"
