// Sphere-triangle distance, written from spec liggghts-walls §4.4 in its operation order.
#include "triangle_contact.h"

namespace dembridge::mesh {

namespace {

constexpr double kSmallTriMesh = 1e-10;

Vec3 unit(int i)
{
  Vec3 b{0.0, 0.0, 0.0};
  b[i] = 1.0;
  return b;
}

TriangleContact none(double r, int sign)
{
  return {kNoContactDistance - r, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, sign, ContactKind::None};
}

TriangleContact at_point(const Vec3 &p, const Vec3 &cp, double r, const Vec3 &bary, int sign, ContactKind kind)
{
  TriangleContact c;
  c.delta = {cp[0] - p[0], cp[1] - p[1], cp[2] - p[2]};
  const double d = std::sqrt((p[0] - cp[0]) * (p[0] - cp[0]) + (p[1] - cp[1]) * (p[1] - cp[1]) +
                             (p[2] - cp[2]) * (p[2] - cp[2]));
  c.dist_minus_r = d - r;
  c.bary = bary;
  c.sign = sign;
  c.kind = kind;
  return c;
}

Vec3 bary_edge(const TriangleMesh &m, int t, int ie, double dfn)
{
  Vec3 b{0.0, 0.0, 0.0};
  b[ie] = 1.0 - dfn / m.edge_len(t, ie);
  b[(ie + 1) % 3] = 1.0 - b[ie];
  return b;
}

Vec3 along(const Vec3 &n, double s, const Vec3 &e) { return {n[0] + s * e[0], n[1] + s * e[1], n[2] + s * e[2]}; }

TriangleContact edge_contact(const TriangleMesh &m, int t, int ie, const Vec3 &p, double r, int sign)
{
  const int ip = (ie + 1) % 3;
  const Vec3 &n = m.node(t, ie);
  const double dfn = dot(sub(p, n), m.edge_vec(t, ie));
  if (dfn < -kSmallTriMesh) {
    if (!m.corner_active(t, ie)) return none(r, sign);
    return at_point(p, n, r, unit(ie), sign, ContactKind::Corner);
  }
  if (dfn > m.edge_len(t, ie) + kSmallTriMesh) {
    if (!m.corner_active(t, ip)) return none(r, sign);
    return at_point(p, m.node(t, ip), r, unit(ip), sign, ContactKind::Corner);
  }
  if (!m.edge_active(t, ie)) return none(r, sign);
  return at_point(p, along(n, dfn, m.edge_vec(t, ie)), r, bary_edge(m, t, ie, dfn), sign, ContactKind::Edge);
}

TriangleContact corner_contact(const TriangleMesh &m, int t, int in, const Vec3 &p, double r, int sign)
{
  const int ip = (in + 1) % 3, ipp = (in + 2) % 3;
  const Vec3 &n = m.node(t, in);
  if (m.obtuse(t) == in) {
    // obtuse corner: the closest point may lie on one of the two adjacent edges
    const Vec3 to_p = sub(p, n);
    double dfn = dot(to_p, m.edge_vec(t, ipp));
    if (dfn < kSmallTriMesh) {
      if (dfn > -m.edge_len(t, ipp)) {
        if (!m.edge_active(t, ipp)) return none(r, sign);
        Vec3 b{0.0, 0.0, 0.0};
        b[in] = 1.0 + dfn / m.edge_len(t, ipp);
        b[ipp] = 1.0 - b[in];
        return at_point(p, along(n, dfn, m.edge_vec(t, ipp)), r, b, sign, ContactKind::Edge);
      }
      if (!m.corner_active(t, ipp)) return none(r, sign);
      return at_point(p, m.node(t, ipp), r, unit(ipp), sign, ContactKind::Corner);
    }
    dfn = dot(to_p, m.edge_vec(t, in));
    if (dfn > -kSmallTriMesh) {
      if (dfn < m.edge_len(t, in)) {
        if (!m.edge_active(t, in)) return none(r, sign);
        return at_point(p, along(n, dfn, m.edge_vec(t, in)), r, bary_edge(m, t, in, dfn), sign, ContactKind::Edge);
      }
      if (!m.corner_active(t, ip)) return none(r, sign);
      return at_point(p, m.node(t, ip), r, unit(ip), sign, ContactKind::Corner);
    }
  }
  if (!m.corner_active(t, in)) return none(r, sign);
  return at_point(p, n, r, unit(in), sign, ContactKind::Corner);
}

}  // namespace

TriangleContact resolve_contact(const TriangleMesh &m, int t, const Vec3 &p, double r)
{
  const Vec3 &n0 = m.node(t, 0);
  const Vec3 n0p{p[0] - n0[0], p[1] - n0[1], p[2] - n0[2]};
  const Vec3 &e0 = m.edge_vec(t, 0), &e2 = m.edge_vec(t, 2);
  const double a = dot(n0p, e0), b = dot(n0p, e2), c = dot(e0, e2);
  const double om = 1 - c * c;
  const double b1 = (a - b * c) / (m.edge_len(t, 0) * om);
  const double b2 = (a * c - b) / (m.edge_len(t, 2) * om);
  const double b0 = 1. - b1 - b2;
  const double invlen = 1. / (2. * m.rbound(t));
  const double thr = -m.options().precision * invlen;
  const int sign = int(b0 > thr) + 2 * int(b1 > thr) + 4 * int(b2 > thr);
  switch (sign) {
    case 7: {
      const Vec3 &sn = m.normal(t);
      const double dn = dot(sn, n0p);
      const Vec3 tmp{sn[0] * dn, sn[1] * dn, sn[2] * dn};
      const Vec3 cs{p[0] - tmp[0], p[1] - tmp[1], p[2] - tmp[2]};
      return at_point(p, cs, r, {b0, b1, b2}, sign, ContactKind::Face);
    }
    case 1: return corner_contact(m, t, 0, p, r, sign);
    case 2: return corner_contact(m, t, 1, p, r, sign);
    case 4: return corner_contact(m, t, 2, p, r, sign);
    case 3: return edge_contact(m, t, 0, p, r, sign);
    case 6: return edge_contact(m, t, 1, p, r, sign);
    case 5: return edge_contact(m, t, 2, p, r, sign);
    default: return none(r, sign);  // sign 0: cannot happen for a valid triangle
  }
}

}  // namespace dembridge::mesh
