"""The ring of parameters/ring-compression.prm (6:3:2 ring: outer diameter 60,
inner 30, height 20 mm; the deck models the upper half, H0 = 10) and its
inner diameter read from a run: the mean over the free inner surface (id 3),
2 x its area / (2 pi h), h the current half height."""
import math

H0, D0 = 10.0, 30.0


def inner_diameter_curve(summary):
    """(height reduction %, change of the inner diameter %) per step of a run."""
    curve = []
    for c in summary["cycles"]:
        h = H0 - c["step"]["stroke"]
        d = 2 * c["boundary_area"]["3"] / (2 * math.pi * h)
        curve.append((100 * (1 - h / H0), 100 * (d / D0 - 1)))
    return curve
