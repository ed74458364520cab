"""The GRANULAR part of CRITICAL(): a per-particle estimate from the pairings that can act (spec §13's
per-particle formula with one contact direction). Parmec HEAD counts only the contacts present when CRITICAL()
is called (none before the first DEM: the largest float for a contact-only model, which makes the usual
`step = ratio * CRITICAL()` of Parmec's own examples meaningless); older Parmec estimated from the pairings."""
import math
import sys


def _pairing(model):
    """(color1, color2) -> (spring, damper) with Parmec's lookup: exact unordered pair, else the default."""
    default, pairs = (0.0, 1.0), {}
    for g in model.granular:
        key = (min(g["color1"], g["color2"]), max(g["color1"], g["color2"]))
        if key == (0, 0):
            default = (g["spring"], g["damper"])
        else:
            pairs[key] = (g["spring"], g["damper"])
    return lambda a, b: pairs.get((min(a, b), max(a, b)), default)


def contact_particle_estimates(model):
    """{particle: (h, omega, xi)}: for each SPHERE the smallest estimate over the colours it can touch
    (other spheres: the heaviest of that colour; obstacle triangles; MESH faces with m_eff of the body), (2/w)(sqrt(1 + xi^2) - xi),
    w = sqrt(k/m_i), xi = e_n/(2 m_i w), e_n = damper 2 sqrt(k m_eff); spheres that touch nothing are absent."""
    if not model.contact_active():
        return {}
    pairing = _pairing(model)
    heaviest = {}
    for p in model.particles:
        if p.contact_sphere:
            heaviest[p.color] = max(heaviest.get(p.color, 0.0), p.mass)
    obstacle_colors = {c for ob in model.obstacles for c in ob["colors"]}
    bodies = [(set(b.triangle_colors), b.mass) for b in model.particles if b.contact_mesh]
    out = {}
    for i, p in enumerate(model.particles):
        if not p.contact_sphere:
            continue
        partners = [(c, 1.0 / (1.0 / p.mass + 1.0 / m)) for c, m in heaviest.items()]
        partners += [(c, p.mass) for c in obstacle_colors]
        partners += [(c, 1.0 / (1.0 / p.mass + 1.0 / mb)) for colors, mb in bodies for c in colors]
        for c, meff in partners:
            k, damper = pairing(p.color, c)
            if k <= 0.0:
                continue
            w = math.sqrt(k / p.mass)
            xi = damper * 2.0 * math.sqrt(k * meff) / (2.0 * p.mass * w)
            h = (2.0 / w) * (math.sqrt(1.0 + xi * xi) - xi)
            if i not in out or h < out[i][0]:
                out[i] = (h, w, xi)
    return out


def contact_critical_step(model):
    """The smallest of contact_particle_estimates (the largest float without contact)."""
    est = contact_particle_estimates(model)
    return min((e[0] for e in est.values()), default=sys.float_info.max)
