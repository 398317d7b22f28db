# The growth family's models (issue 26 item 1), sourced by scripts/growth.sh and tests/growth.sh:
#   growth_chain N     a spatial serial chain of N driven revolutes (axes z, x, y in turn), N bodies
#   growth_tree N      a branched tree of N driven revolutes: body i hangs from body (i - 1) / 2
#                      (a binary tree, depth log2 N), N bodies
#   growth_chain_nojac N, growth_tree_nojac N: the same with `kernel: {jacobians: []}` (a kernel
#                      without the bodies' and points' Jacobians: 6 x N entries each, N^2 in all)
#   growth_loops N     N RSUR loops chained in series, one driver: loop 1 is models/rsur.yaml; the
#                      rocker of loop j is the crank of loop j + 1, whose geometry is loop j's turned
#                      by the cyclic rotation R (x -> y -> z -> x) so that its crank axis is loop j's
#                      rocker axis; 2N + 1 moving bodies, 3N + 1 joints, N circuits, mobility 1
#   growth_fourbars N  N planar four-bars in series, one driver (issue 25 item 5): loop j's input
#                      link turns about A_j = ((j - 1) d, 0), its rocker about B_j = (j d, 0); the
#                      rocker of loop j is the input link of loop j + 1 (its pin P_(j+1) on the
#                      line B_j C_j). A Grashof crank-rocker (input 1, coupler 3, rocker 2.5,
#                      ground 3, in units of l): every input angle assembles, so each loop follows
#                      the one before it over the crank's whole turn. 3N moving bodies, 4N joints.
# Each prints the description on stdout. Geometry in numbers (printed once, used in both bodies of
# a joint): the text grows linearly with N.

# A serial chain or a binary tree of N revolutes with masses, every joint driven.
growth_revolutes() {  # KIND N [nojac]
  awk -v kind="$1" -v n="$2" -v nojac="${3:-}" 'BEGIN {
    printf "name: %s%d\ndimension: spatial\ngravity: [0, 0, -9.81]\n", kind, n
    printf "parameters:\n  w: {value: 3, unit: rad/s}\n  m: {value: 0.1, unit: kg}\n"
    printf "bodies:\n  - {name: base, ground: true, points: {P0: [0, 0, 0]}}\n"
    split("[0, 0, 1]|[1, 0, 0]|[0, 1, 0]", axis, "|")
    for (i = 1; i <= n; i++) {
      parent[i] = kind == "chain" ? i - 1 : int((i - 1) / 2)
      # body i reaches 0.05 below its parent, shifted sideways in a tree so siblings differ
      x[i] = x[parent[i]] + (kind == "chain" ? 0 : (i % 2 ? 0.02 : -0.02))
      z[i] = z[parent[i]] - 0.05
      printf "  - name: b%d\n", i
      printf "    points: {P%d: [%.4f, 0, %.4f], P%d: [%.4f, 0, %.4f]}\n", parent[i], x[parent[i]], z[parent[i]], i, x[i], z[i]
      printf "    mass: {mass: m, com: [%.4f, 0.001, %.4f], inertia: [[1e-4, 0, 0], [0, 1e-4, 0], [0, 0, 5e-5]]}\n", (x[i] + x[parent[i]]) / 2, z[i] + 0.025
    }
    print "joints:"
    for (i = 1; i <= n; i++)
      printf "  - {name: j%d, type: revolute, first: %s, second: b%d, s: %s, s0: P%d}\n", i, parent[i] ? "b" parent[i] : "base", i, axis[i % 3 + 1], parent[i]
    print "drivers:"
    for (i = 1; i <= n; i++) printf "  - {name: q%d, joint: j%d, kind: angle, value: 0.1*sin(w*t + 0.1*%d)}\n", i, i, i
    print "step: {t0: 0, t1: 2*pi/w, samples: 11}"
    if (nojac) print "kernel: {jacobians: []}"
  }'
}
growth_chain() { growth_revolutes chain "$1"; }
growth_tree() { growth_revolutes tree "$1"; }
growth_chain_nojac() { growth_revolutes chain "$1" nojac; }
growth_tree_nojac() { growth_revolutes tree "$1" nojac; }

growth_loops() {  # N
  awk -v n="$1" 'BEGIN {
    a = 0.02; d = 0.1; h = 0.05; c = 0.07
    printf "name: loops%d\ndimension: spatial\ngravity: [0, 0, -9.81]\n", n
    printf "parameters:\n  r: {value: 0.004, unit: m}\n  rho: {value: 2700, unit: kg/m^3}\n  w: {value: 2, unit: rad/s}\n"
    # loop j (1..n): crank pivot P_j (P_1 = origin, P_{j+1} = D_j), turned by R^(j-1)
    px = 0; py = 0; pz = 0
    for (j = 1; j <= n; j++) {
      turn(a, 0, 0, j - 1); B[j] = vec(px + tx, py + ty, pz + tz)
      turn(0, d, h, j - 1); dx = px + tx; dy = py + ty; dz = pz + tz; D[j] = vec(dx, dy, dz)
      turn(0, 0, c, j - 1); C[j] = vec(dx + tx, dy + ty, dz + tz)
      turn(1, 0, 0, j - 1); S[j] = vec(tx, ty, tz)   # rocker axis, first universal axis
      turn(0, 0, 1, j - 1); S2[j] = vec(tx, ty, tz)  # crank axis, second universal axis
      px = dx; py = dy; pz = dz
    }
    print "bodies:"
    printf "  - name: ground\n    ground: true\n    points: {A: [0, 0, 0]"
    for (j = 1; j <= n; j++) printf ", D%d: %s", j, D[j]
    print "}"
    printf "  - name: crank\n    points: {A: [0, 0, 0], B1: %s}\n    mass: {bar: [A, B1], radius: r, density: rho}\n", B[1]
    for (j = 1; j <= n; j++) {
      printf "  - name: coupler%d\n    points: {B%d: %s, C%d: %s}\n", j, j, B[j], j, C[j]
      printf "    mass: {bar: [B%d, C%d], radius: r, density: rho}\n", j, j
      printf "  - name: rocker%d\n    points: {D%d: %s, C%d: %s", j, j, D[j], j, C[j]
      if (j < n) printf ", B%d: %s", j + 1, B[j + 1]
      printf "}\n    mass: {bar: [D%d, C%d], radius: r, density: rho}\n", j, j
    }
    print "joints:"
    print "  - {name: jA, type: revolute, first: ground, second: crank, s: [0, 0, 1], s0: A}"
    for (j = 1; j <= n; j++) {
      printf "  - {name: jB%d, type: spherical, first: %s, second: coupler%d, s0: B%d}\n", j, j == 1 ? "crank" : "rocker" (j - 1), j, j
      printf "  - {name: jC%d, type: universal, first: coupler%d, second: rocker%d, s: %s, s2: %s, s0: C%d}\n", j, j, j, S[j], S2[j], j
      printf "  - {name: jD%d, type: revolute, first: ground, second: rocker%d, s: %s, s0: D%d}\n", j, j, S[j], j
    }
    print "drivers:\n  - {name: theta, joint: jA, kind: angle, value: w*t}"
    print "step: {t0: 0, t1: 2*pi/w, samples: 181}"
  }
  # (x, y, z) turned k times by R: R (x, y, z) = (z, x, y), so R e_x = e_y, R e_z = e_x
  function turn(x, y, z, k,   i, s) {
    for (i = 0; i < k % 3; i++) { s = z; z = y; y = x; x = s }
    tx = x; ty = y; tz = z
  }
  function vec(x, y, z) { return sprintf("[%.10g, %.10g, %.10g]", x, y, z) }'
}

growth_fourbars() {  # N
  awk -v n="$1" 'BEGIN {
    a = 1; b = 3; c = 2.5; d = 3; pi = atan2(0, -1)
    printf "name: fourbars%d\ndimension: planar\ngravity: [0, -9.81]\n", n
    printf "parameters:\n  l: {value: 0.02, unit: m}\n  w: {value: 2, unit: rad/s}\n"
    printf "  rho: {value: 2700, unit: kg/m^3}\n  bar_w: {value: 0.01, unit: m}\n  bar_t: {value: 0.004, unit: m}\n"
    print "bodies:"
    printf "  - name: ground\n    ground: true\n    points: {A1: [0, 0]"
    for (j = 1; j <= n; j++) printf ", B%d: [%g*l, 0]", j, j * d
    print "}"
    # the assembly at t0 (crank angle pi/2), loop by loop: C_j on the left of P_j -> B_j
    theta = pi / 2
    mass = "width: bar_w, thickness: bar_t, density: rho"
    printf "  - name: crank\n    points: {A1: [0, 0], P1: [%g*l, 0]}\n", a
    printf "    mass: {bar: [A1, P1], %s}\n    assembly: %.12g\n", mass, theta
    for (j = 1; j <= n; j++) {
      px = (j - 1) * d + a * cos(theta); py = a * sin(theta)
      ex = j * d - px; ey = -py; L = sqrt(ex * ex + ey * ey)
      along = (b * b - c * c + L * L) / (2 * L); h = sqrt(b * b - along * along)
      cx = px + (along * ex - h * ey) / L; cy = py + (along * ey + h * ex) / L
      printf "  - name: coupler%d\n    points: {P%d: [0, 0], C%d: [%g*l, 0]}\n", j, j, j, b
      printf "    mass: {bar: [P%d, C%d], %s}\n    assembly: %.12g\n", j, j, mass, atan2(cy - py, cx - px)
      theta = atan2(cy, cx - j * d)
      printf "  - name: rocker%d\n    points: {B%d: [0, 0], C%d: [%g*l, 0]", j, j, j, c
      if (j < n) printf ", P%d: [%g*l, 0]", j + 1, a
      printf "}\n    mass: {bar: [B%d, C%d], %s}\n    assembly: %.12g\n", j, j, mass, theta
    }
    print "joints:"
    print "  - {name: jA1, type: revolute, first: ground, second: crank, point: A1}"
    for (j = 1; j <= n; j++) {
      printf "  - {name: jP%d, type: revolute, first: %s, second: coupler%d, point: P%d}\n", j, j == 1 ? "crank" : "rocker" (j - 1), j, j
      printf "  - {name: jC%d, type: revolute, first: rocker%d, second: coupler%d, point: C%d}\n", j, j, j, j
      printf "  - {name: jB%d, type: revolute, first: ground, second: rocker%d, point: B%d}\n", j, j, j
    }
    print "drivers:\n  - {name: theta, joint: jA1, kind: angle, value: pi/2 + w*t}"
    print "step: {t0: 0, t1: 2*pi/w, samples: 181}"
  }'
}
