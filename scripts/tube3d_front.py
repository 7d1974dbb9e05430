#!/usr/bin/python3
"""The speed of tube3d's pressure wave by a defined criterion, against the long-wave
estimates of an elastic tube.

  /usr/bin/python3 scripts/tube3d_front.py RUN[=LABEL]... [--csv F]

RUN: a tube3d run directory (probes.csv and summary.json). Its probes are the wall's
displacement at (0.5, 0, z) on the interface, z = 1.25, 2.5, 3.75; the radial displacement
there is dx. The front arrives at a station when dx first reaches half of its largest value
at that station (linear interpolation between steps); the speed is the least-squares slope
of z against those arrival times, and each pair of neighbouring stations gives its own.
The run must be long enough for the pulse's peak to pass the last station (the script
says when it has not).

The estimates use the run's own parameters (summary.json options: E, nu, the fluid density)
and the tube's radii a = 0.5 (fluid) and b = 0.6 (outside of the wall), with the wave speed
of the long-wave, inviscid theory c = 1/sqrt(rho D) and D = (dA/dp)/A = 2 u_a/(a p), u_a
the radial displacement of the inner surface under a pressure p:
  thin wall (Moens-Korteweg)      u_a = p a^2 / (E h),                  h = b - a
  thin wall, plane strain         u_a = p a^2 (1 - nu^2) / (E h)
  thick wall, plane stress (Lame) u_a = p a / E ((a^2 + b^2)/(b^2 - a^2) + nu)
  thick wall, plane strain (Lame) u_a = p a (1 + nu) / E ((1 - 2 nu) a^2 + b^2)/(b^2 - a^2)
(plane stress: a free axial stress; plane strain: no axial strain, as clamped ends hold a
long tube). These hold for waves much longer than the radius. The inlet pulse lasts T
(-parameter_duration): at the angular frequency w = 2 pi / (2 T) of a pulse of that length
the wave is about 2.5 radii long, and the fluid's radial inertia and the wall's slow it.
The script also gives that speed, from the dispersion relation of an inviscid fluid in a
tube whose wall has the thick wall's radial stiffness K = p / u_a and the mass rho_s h per
unit area:
  c^2 = (K - rho_s h w^2) I1(k a) / (rho k I0(k a)),   c = w / k
(I0, I1: modified Bessel functions; c^2 -> K a / (2 rho) as k a -> 0). Markdown to stdout."""
import argparse, csv, math, os, sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fsiopt_runs as fr  # noqa: E402

INNER, OUTER = 0.5, 0.6   # the tube's radii (meshes/tube3d-section.geoinc)


def estimates(E, nu, rho, a=INNER, b=OUTER):
    h = b - a
    u_over_pa = {   # u_a / (p a)
        "thin wall (Moens-Korteweg)": a / (E * h),
        "thin wall, plane strain": a * (1 - nu ** 2) / (E * h),
        "thick wall, plane stress": ((a * a + b * b) / (b * b - a * a) + nu) / E,
        "thick wall, plane strain": (1 + nu) * ((1 - 2 * nu) * a * a + b * b) / ((b * b - a * a) * E),
    }
    return {k: 1.0 / math.sqrt(rho * 2 * v) for k, v in u_over_pa.items()}


def bessel_i(n, x):
    """I0 or I1 by their series"""
    term, total = (1.0 if n == 0 else x / 2), 0.0
    for m in range(60):
        total += term
        term *= (x / 2) ** 2 / ((m + 1) * (m + 1 + n))
    return total


def dispersive(E, nu, rho, rho_s, period, a=INNER, b=OUTER):
    """{name: c} at the angular frequency 2 pi / period, thick-wall stiffness, by fixed point"""
    h, w = b - a, 2 * math.pi / period
    stiffness = {"thick wall, plane stress": E / (a * ((a * a + b * b) / (b * b - a * a) + nu)),
                 "thick wall, plane strain": E * (b * b - a * a) / (a * (1 + nu) * ((1 - 2 * nu) * a * a + b * b))}
    out = {}
    for name, K in stiffness.items():
        c = math.sqrt(K * a / (2 * rho))
        for _ in range(200):
            k = w / c
            c = math.sqrt((K - rho_s * h * w * w) * bessel_i(1, k * a) / (rho * k * bessel_i(0, k * a)))
        out[name + ", w = 2 pi/%.3g s (ka = %.2f)" % (period, w / c * a)] = c
    return out


def arrivals(run):
    rows = list(csv.reader(open(os.path.join(run, "probes.csv"))))
    head = [fr.column_name(n) for n in rows[0]]
    data = [[float(v) for v in r] for r in rows[1:]]
    t = [r[0] for r in data]
    out = []
    for c, name in enumerate(head):
        if not name.startswith("dx("):
            continue
        z = float(name[3:-1].split(";")[2])
        d = [r[c] for r in data]
        peak = max(d)
        k = max(range(len(d)), key=lambda i: d[i])
        if k == len(d) - 1:
            sys.exit("tube3d_front: %s: dx at z = %g still grows at the run's end (t = %g): run longer" % (run, z, t[-1]))
        half = 0.5 * peak
        i = next(i for i in range(len(d)) if d[i] >= half)
        ta = t[i] if i == 0 else t[i - 1] + (half - d[i - 1]) * (t[i] - t[i - 1]) / (d[i] - d[i - 1])
        out.append((z, ta, peak))
    return out


def slope(points):
    n = len(points)
    mt = sum(p[1] for p in points) / n
    mz = sum(p[0] for p in points) / n
    return sum((p[1] - mt) * (p[0] - mz) for p in points) / sum((p[1] - mt) ** 2 for p in points)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="run directories, RUN or RUN=LABEL")
    ap.add_argument("--csv", help="also write the table as CSV")
    args = ap.parse_args()
    rows = []
    params = None
    for spec in args.runs:
        run, _, label = spec.partition("=")
        s = fr.read_summary(run)
        if not s:
            sys.exit("tube3d_front: %s: no summary.json" % run)
        o = s.get("options", {})
        p = (float(o["-structure_youngs_modulus"]), float(o["-structure_poisson_ratio"]), float(o["-fluid_density"]),
             float(o["-structure_density"]), float(o.get("-parameter_duration", "0.003")))
        if params and p != params:
            sys.exit("tube3d_front: %s has other parameters (E, nu, rho) %s than %s" % (run, p, params))
        params = p
        a = arrivals(run)
        pair = ["%.1f" % ((a[i + 1][0] - a[i][0]) / (a[i + 1][1] - a[i][1])) for i in range(len(a) - 1)]
        rows.append({"run": label or run, "unknowns": s["fluid_dofs"] + s["structure_dofs"], "dt": s["dt"],
                     "arrivals_ms": " ".join("%.3f" % (x[1] * 1e3) for x in a), "speed": slope(a),
                     "pairs": " ".join(pair), "peaks": " ".join("%.3e" % x[2] for x in a)})
    print("| run | unknowns | dt | arrival of half the peak at z = %s (ms) | speed (cm/s) | pairwise | peak dx |" %
          ", ".join("%g" % x[0] for x in arrivals(args.runs[0].partition("=")[0])))
    print("|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %d | %g | %s | %.1f | %s | %s |" % (r["run"], r["unknowns"], r["dt"], r["arrivals_ms"], r["speed"],
                                                       r["pairs"], r["peaks"]))
    E, nu, rho, rho_s, duration = params
    print("\nEstimates (E = %g, nu = %g, rho = %g, rho_s = %g, a = %g, b = %g; the pulse lasts %g s):\n" %
          (E, nu, rho, rho_s, INNER, OUTER, duration))
    print("| estimate | c (cm/s) | measured / c (the last run) |\n|---|---|---|")
    both = dict(("long wave, " + k, c) for k, c in estimates(E, nu, rho).items())
    both.update(dispersive(E, nu, rho, rho_s, 2 * duration))
    for k, c in both.items():
        print("| %s | %.1f | %.3f |" % (k, c, rows[-1]["speed"] / c))
    if args.csv:
        fr.write_csv(args.csv, rows, list(rows[0].keys()))


if __name__ == "__main__":
    main()
