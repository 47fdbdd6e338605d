#!/usr/bin/env python3
"""Writes models/iltis_vehicle_benchmark.ron and models/iltis_bump.ron: the IAVSD "Bombardier
Iltis" benchmark vehicle (scene C0 of docs/scenes.md section 3.3) from the front-left corner of
docs/scenes.md section 2.3, mirrored to the four corners as section 2.1 says; and
models/iltis_suspension.ron, scene B (docs/scenes.md section 2.7, the project specification's
sections 2.7-2.11), from the same corner data; and models/iltis_vehicle.ron, scene C (the
specification's sections 3.4-3.7), the whole vehicle from scene B's corner. Every number is
the one of docs/scenes.md sections 2.2-2.5 and 3.1-3.2 (sources S9: ovankerm/IAVSD_ILTIS at
commit 18c4286, files Jeep.mbs, main.c, user_LinkForces.c, user_ExtForces.c, GroundContact.c).

Run from the repository root: python3 models/generate_iltis.py (no dependencies). The .ron
files it writes are committed; edit this script, not them.
"""
import math

# docs/scenes.md 2.3, front-left corner (y > 0), vehicle frame V at the nominal position.
FRONT_LEFT = {
    "A0": (0.970, 0.259, 0.302),   # A-arm chassis pivot
    "B": (0.970, 0.572, 0.229),    # ball joint A-arm / carrier
    "L0": (0.970, 0.1585, 0.600),  # leaf-spring link, chassis pivot
    "U": (0.970, 0.488, 0.531),    # leaf-spring link outer end = upper carrier joint
    "W": (0.970, 0.615, 0.356),    # wheel centre
    "T0": (0.830, 0.070, 0.600),   # tie rod, rack end (rack fixed to the chassis)
    "T1": (0.830, 0.448, 0.531),   # tie rod, steering-arm end
    "S0": (1.045, 0.297, 0.632),   # strut top (chassis)
    "S1": (1.045, 0.500, 0.241),   # strut bottom (A-arm)
    "E": (0.970, 0.488, 0.707),    # leaf element chassis end, above U (2.4)
}
CHASSIS_CG = (0.0, 0.0, 0.570)  # 2.1, 2.2
X_FRONT, X_REAR = 0.970, -1.047  # 2.3
# 2.5: unloaded radii front / rear; 460000 N/m; no tyre damping.
RADIUS = {"f": 0.364325, "r": 0.363812}
TYRE_STIFFNESS = 460000.0
# 2.4: the strut (S9 "Bumper") spring and damper, tension positive.
STRUT_SPRING = [-4.0092e6, 2.8397e7, -6.7061e7, 5.2796e7]
STRUT_DAMPER_LOW = [-416.42, 1844.3]           # v < -0.20 m/s
STRUT_DAMPER_MID = [0.0, 9945.627, 33955.72, -59832.25, -395651.0]
STRUT_DAMPER_HIGH = [1919.1638, 1634.727]      # v > 0.21 m/s
# 2.4: leaf element, s = z(E) - z(U) along chassis z, l = s - 0.100;
# F = k (l - 0.152) for l >= 0.006, k (0.006 - 0.152) + k_stop (l - 0.006) below.
LEAF_K, LEAF_K_STOP = 35906.0, 1.0e7


def corner_points(corner):
    """The hard points of corner fl, fr, rl or rr (2.1: right = y mirrored; rear = x
    mirrored about the rear axle, x_rear = -1.047 - (x_front - 0.970))."""
    axle, side = corner[0], corner[1]
    out = {}
    for name, (x, y, z) in FRONT_LEFT.items():
        if axle == "r":
            x = X_REAR - (x - X_FRONT)
        if side == "r":
            y = -y
        out[name] = (x, y, z)
    return out


def sub(a, b):
    return tuple(p - q for p, q in zip(a, b))


def dot(a, b):
    return sum(p * q for p, q in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def unit(a):
    n = math.sqrt(dot(a, a))
    return tuple(p / n for p in a)


def number(c):
    text = f"{c:.10g}"
    return text if any(ch in text for ch in ".en") else text + ".0"


def vec(v):
    return "[" + ", ".join(number(c) for c in v) + "]"


def marker(name, v):
    return f'(name: "{name}", position: {vec(v)})'


def chassis():
    markers = [marker("cg", (0.0, 0.0, 0.0))]
    for c in ["fl", "fr", "rl", "rr"]:
        p = corner_points(c)
        for n in ["A0", "L0", "T0", "S0", "E"]:
            markers.append(marker(f"{n}_{c}", sub(p[n], CHASSIS_CG)))
    body = f'''        (name: "chassis", origin: {vec(CHASSIS_CG)},
         // 2.2: 1260 kg at the centre of mass, Ixx 130, Iyy 1620, Izz 1670 kg m^2 [S9 Jeep.mbs].
         model: Rigid(mass: 1260.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([130.0, 1620.0, 1670.0])),
         markers: [
            {(","+chr(10)+"            ").join(markers)},
         ]),'''
    return body


def aarm(c):
    """Lower A-arm (2.2): 6.0 kg, centre of mass on B->A0 0.16073 m from B; inertias about
    the longitudinal axis, the arm's own axis B->A0 and the normal to both. Frame: origin B,
    x forward, y along B->A0 (the arm axes of 2.8)."""
    p = corner_points(c)
    ex = (1.0, 0.0, 0.0)
    ey = unit(sub(p["A0"], p["B"]))
    ez = cross(ex, ey)
    local = lambda v: (dot(sub(v, p["B"]), ex), dot(sub(v, p["B"]), ey), dot(sub(v, p["B"]), ez))
    markers = [marker("B", (0.0, 0.0, 0.0)), marker("A0", local(p["A0"])), marker("S1", local(p["S1"]))]
    return f'''        (name: "aarm_{c}", origin: {vec(p["B"])}, orientation: Axes(x: {vec(ex)}, y: {vec(ey)}),
         model: Rigid(mass: 6.0, center_of_mass: [0.0, 0.16073, 0.0], inertia: Diagonal([0.052099, 0.023235, 0.068864])),
         markers: [{", ".join(markers)}]),'''


def carrier(c):
    """Wheel + carrier lumped (2.2): 57.35 kg at W, Ixx = Izz = 1.2402, Iyy = 1.908 (spin
    axis), vehicle axes; the wheel welded to the carrier (2.3, "Joints in our model")."""
    p = corner_points(c)
    markers = [marker("W", (0.0, 0.0, 0.0))] + [marker(n, sub(p[n], p["W"])) for n in ["B", "U", "T1"]]
    return f'''        (name: "carrier_{c}", origin: {vec(p["W"])},
         model: Rigid(mass: 57.35, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([1.2402, 1.908, 1.2402])),
         markers: [{", ".join(markers)}]),'''


def joints(c):
    return f'''        (name: "aarm_pivot_{c}", kind: Revolute(axis: Some([1.0, 0.0, 0.0])), body1: "chassis", marker1: "A0_{c}", body2: "aarm_{c}", marker2: "A0"),
        (name: "ball_joint_{c}", kind: Spherical, body1: "aarm_{c}", marker1: "B", body2: "carrier_{c}", marker2: "B"),'''


def constraints(c):
    return f'''        // The massless leaf-spring link L0-U (revolute about chassis x at L0, spherical at U):
        // U stays at its distance from L0 in the chassis-fixed plane through L0 normal to x.
        Distance(name: "leaf_link_{c}", body1: "chassis", marker1: "L0_{c}", body2: "carrier_{c}", marker2: "U", length: None),
        PointInPlane(name: "leaf_link_plane_{c}", body1: "chassis", marker1: "L0_{c}", normal: [1.0, 0.0, 0.0], body2: "carrier_{c}", marker2: "U"),
        // The massless tie rod T0-T1, the rack fixed (2.3, 3.1).
        Distance(name: "tie_rod_{c}", body1: "chassis", marker1: "T0_{c}", body2: "carrier_{c}", marker2: "T1", length: None),'''


def lateral(c, speed):
    return 0.0 if speed == 0.0 else round(CORNERING[c[0]] / speed, 1)


def poly(coefficients, about=None):
    cs = ", ".join(f"{x!r}" for x in coefficients)
    if about is None:
        return f"Polynomial(coefficients: [{cs}])"
    return f"Polynomial(about: {about!r}, coefficients: [{cs}])"


# scenes.md 3.4: S9's cornering stiffness at the static loads (user_ExtForces.c, 41641 / 40162
# N/rad) over the forward speed, the linear lateral damper F_y = -(C_alpha / V) v_y that stands
# for S9's Calspan slip force on the bump (the contact points move sideways as the suspension
# travels, +0.19 mm per mm of jounce, so the in-phase bump has lateral tyre forces too).
CORNERING = {"f": 41641.0, "r": 40162.0}


def forces(c, road, contact, speed):
    k, ks = LEAF_K, LEAF_K_STOP
    # In s: the stop piece about s = 0.106 (l = 0.006), the leaf about s = 0.100 (l = 0).
    leaf_stop = poly([round(k * (0.006 - 0.152), 6), ks], about=0.106)
    leaf = poly([round(-0.152 * k, 6), k], about=0.1)
    damper = (f"Piecewise(breakpoints: [-0.2, 0.21], pieces: [{poly(STRUT_DAMPER_LOW)}, "
              f"{poly(STRUT_DAMPER_MID)}, {poly(STRUT_DAMPER_HIGH)}])")
    return f'''        Link(name: "strut_{c}", body1: "chassis", marker1: "S0_{c}", body2: "aarm_{c}", marker2: "S1",
             spring: {poly(STRUT_SPRING)},
             damper: {damper},
             axis: None),
        Link(name: "leaf_{c}", body1: "chassis", marker1: "E_{c}", body2: "carrier_{c}", marker2: "U",
             spring: Piecewise(breakpoints: [0.106], pieces: [{leaf_stop}, {leaf}]),
             damper: Zero,
             axis: Some([0.0, 0.0, -1.0])),
        Tyre(name: "tyre_{c}", body: "carrier_{c}", marker: "W", road: "{road}", radius: {RADIUS[c[0]]}, stiffness: {TYRE_STIFFNESS}, contact: {contact}, lateral_damping: {lateral(c, speed)}),'''


SENSORS = '''        (name: "chassis_x", kind: Position(body: "chassis", marker: "cg", component: X)),
        (name: "chassis_z", kind: Position(body: "chassis", marker: "cg", component: Z)),
        (name: "chassis_pitch", kind: Angle(body: "chassis", axis: Y)),
        (name: "chassis_roll", kind: Angle(body: "chassis", axis: X)),
        (name: "wheel_fl_z", kind: Position(body: "carrier_fl", marker: "W", component: Z)),
        (name: "wheel_rl_z", kind: Position(body: "carrier_rl", marker: "W", component: Z)),
        (name: "tyre_fl", kind: ElementForce(force: "tyre_fl")),
        (name: "tyre_fr", kind: ElementForce(force: "tyre_fr")),
        (name: "tyre_rl", kind: ElementForce(force: "tyre_rl")),
        (name: "tyre_rr", kind: ElementForce(force: "tyre_rr")),
        (name: "strut_fl", kind: ElementForce(force: "strut_fl")),
        (name: "strut_rl", kind: ElementForce(force: "strut_rl")),
        (name: "leaf_fl", kind: ElementForce(force: "leaf_fl")),
        (name: "leaf_rl", kind: ElementForce(force: "leaf_rl")),'''


def scene(name, description, header, road_block, contact, velocity, solver):
    corners = ["fl", "fr", "rl", "rr"]
    bodies = [chassis()] + [aarm(c) for c in corners] + [carrier(c) for c in corners]
    return f'''{header}
(
    name: "{name}",
    description: "{description}",
    dim: Spatial,
    gravity: [0.0, 0.0, -9.81],
    initial_velocity: {vec(velocity)},
    ground: [(name: "cg0", position: {vec(CHASSIS_CG)})],
    bodies: [
{chr(10).join(bodies)}
    ],
    joints: [
        (name: "chassis_float", kind: Free, body1: "ground", marker1: "cg0", body2: "chassis", marker2: "cg"),
{chr(10).join(joints(c) for c in corners)}
    ],
    constraints: [
{chr(10).join(constraints(c) for c in corners)}
    ],
    forces: [
{chr(10).join(forces(c, "road", contact, velocity[0]) for c in corners)}
    ],
    roads: [
{road_block}
    ],
    sensors: [
{SENSORS}
    ],
    solver: {solver},
)
'''


COMMON = """// Generated by models/generate_iltis.py from docs/scenes.md 2.1-3.3 (edit the script, not this file).
// The IAVSD "Bombardier Iltis" benchmark vehicle as implemented in Robotran by S9
// (github ovankerm/IAVSD_ILTIS, commit 18c4286; benchmark: Frik, Leister & Schwartz, Vehicle
// System Dynamics 22 (1993) 215-253). Vehicle frame: x forward, y left, z up, origin on the flat
// road below the chassis centre of mass in the nominal position; front-left = the corner at y > 0.
// Bodies: the chassis (free, 6 DOF), per corner the lower A-arm (revolute about x through A0 to
// the chassis, ball joint B to the carrier) and the wheel carrier with the wheel welded to it;
// the leaf-spring link and the tie rod are massless and written as constraints (scenes.md 3.3).
// Forces per corner: the strut (cubic spring, piecewise-quartic damper), the leaf element along
// chassis z with its 70 mm bump stop (2.4), the vertical tyre 460 kN/m without damping (2.5).
// Element forces are tension-positive (2.1)."""


# ---------------------------------------------------------------------------------------------
# Scene B (docs/scenes.md 2.7-2.11): one front-left corner with a quarter chassis, the A-arm,
# the leaf-spring link and the tie rod as beam bodies (2.8), rigid unless switched flexible.
# ---------------------------------------------------------------------------------------------

# 2.7: the front-left share of the chassis, 1260 x 1.047 / 2.017 / 2 (DERIVED).
QUARTER_CHASSIS_MASS = 327.03
# 2.8: steel as in section 1 (E, rho, nu).
STEEL = "(young_modulus: 2.1e11, density: 7850.0, poisson_ratio: Some(0.3))"
# 2.8 sections: A-arm tube OD 50 x 7.94; leaf 60 (along x) x 12 (vertical); tie rod tube 22 x 3.
AARM_SECTION = "General(area: 1.0487e-3, iy: 2.402e-7, iz: 2.402e-7, torsion_j: 4.804e-7)"
# With k = body x (forward) the element y axis is the leaf's vertical: I_z = 60 x 12^3 / 12 mm^4
# (vertical bending), I_y = 12 x 60^3 / 12 mm^4 (lateral), docs/methods.md 1.2.
LEAF_LINK_SECTION = "General(area: 7.2e-4, iy: 2.16e-7, iz: 8.64e-9, torsion_j: 3.02e-8)"
TIE_ROD_SECTION = "General(area: 1.791e-4, iy: 8.28e-9, iz: 8.28e-9, torsion_j: 1.66e-8)"
AARM_HALF_SPACING = 0.108      # 2.8: P+- = A0 +- (0.108, 0, 0)
AARM_BRACKET_STATION = 0.22665  # 2.8: N_S = B + 0.22665 (P+ - B)
# 2.9: C = beta K, beta = 2 zeta / omega_1, zeta = 0.02; omega_1 = 2 pi f_1, f_1 the first
# fixed-interface frequency of each body as `flexmbd modes` prints it for that body's spec (the
# Beam((...)) of the model file saved alone; 2.8 expects 388 Hz and 585 Hz for the two links).
ZETA = 0.02
FIRST_FREQUENCY_HZ = {"aarm": 1020.7630, "leaf_link": 387.9533, "tie_rod": 583.8083}
# 2.10: the moving road under a fixed corner, written as the corner riding a sled over a
# fixed road (Galilean equivalent): the sled moves along x at SLED_SPEED, the road steps down
# 0.20 m where the wheel centre is at t = 0.5 s.
SLED_SPEED = 1.0
DROP_TIME, DROP_HEIGHT = 0.5, 0.20


def damping(body):
    f1 = FIRST_FREQUENCY_HZ[body]
    beta = 2.0 * ZETA / (2.0 * math.pi * f1)
    return f"StiffnessProportional(a_k: {beta:.6g})"


def node(name, v):
    return f'(name: "{name}", position: {vec(v)})'


def pivots(c):
    """P+ and P- of 2.8: A0 -+ the half spacing along x; on the rear axle mirrored in x about
    it (2.1, 3.1), so that P+ ("Pf", the pivot of the leg carrying the strut bracket) is on the
    strut's side of the axle, behind it."""
    a0 = corner_points(c)["A0"]
    d = AARM_HALF_SPACING if c[0] == "f" else -AARM_HALF_SPACING
    return ((a0[0] + d, a0[1], a0[2]), (a0[0] - d, a0[1], a0[2]))


def aarm_beam(c):
    """The A-arm as the beam frame of 2.8, in the arm axes of 2.2/2.8 (origin B, x forward,
    y along B->A0, z normal to the arm plane); nodes B, P+, P-, N_S, S1 (0..4)."""
    p = corner_points(c)
    ex = (1.0, 0.0, 0.0)
    ey = unit(sub(p["A0"], p["B"]))
    ez = cross(ex, ey)
    local = lambda v: tuple(round(dot(sub(v, p["B"]), e), 9) + 0.0 for e in (ex, ey, ez))
    plus, minus = pivots(c)
    ns = tuple(b + AARM_BRACKET_STATION * (q - b) for b, q in zip(p["B"], plus))
    pts = {"B": local(p["B"]), "Pf": local(plus), "Pr": local(minus), "N_S": local(ns), "S1": local(p["S1"])}
    nodes = ", ".join(node(n, pts[n]) for n in ["B", "Pf", "Pr", "N_S", "S1"])
    markers = ", ".join(marker(n, pts[n]) for n in ["B", "Pf", "Pr", "S1"])
    return f'''        // 2.8 A-arm: a flat V B-P+ (via N_S, 1 + 3 elements), B-P- (4), the strut bracket N_S-S1
        // (1), tube OD 50 x 7.94 mm; 6.000 kg (DERIVED). Frame (DEVIATION from 2.8, whose 7 frame
        // DOFs are hyperstatic and refused): isostatic, P+ translations and rotation about the
        // pivot axis (arm x) and P- translations normal to it; static modes P- along the axis,
        // B and S1 (7); 2 fixed-interface modes: 9 elastic coordinates (2.8: 8).
        (name: "aarm_{c}", origin: {vec(p["B"])}, orientation: Axes(x: {vec(ex)}, y: {vec(ey)}), flexible: false,
         model: Beam((
            dim: Spatial,
            material: {STEEL},
            section: {AARM_SECTION},
            geometry: (
                elements_per_segment: 1,
                nodes: [{nodes}],
                members: [(from: "B", to: "N_S"), (from: "N_S", to: "Pf", elements: Some(3)),
                          (from: "B", to: "Pr", elements: Some(4)), (from: "N_S", to: "S1")],
            ),
            frame: Dofs([(node: 1, dof: Ux), (node: 1, dof: Uy), (node: 1, dof: Uz), (node: 1, dof: Rx),
                         (node: 2, dof: Uy), (node: 2, dof: Uz)]),
            boundary: [(node: 2, dof: Ux), (node: 0, dof: Ux), (node: 0, dof: Uy), (node: 0, dof: Uz),
                       (node: 4, dof: Ux), (node: 4, dof: Uy), (node: 4, dof: Uz)],
            normal_modes: 2,
            damping: {damping("aarm")},
         )),
         markers: [{markers}]),'''


def straight_beam(name, body, c, a, b, section, comment):
    """A straight 4-element beam from hard point a to b (2.8), body axes = vehicle axes with
    the origin at a; frame clamped at a, static modes the translations of b, 2 normal modes."""
    p = corner_points(c)
    d = sub(p[b], p[a])
    return f'''        // {comment}
        (name: "{name}", origin: {vec(p[a])}, flexible: false,
         model: Beam((
            dim: Spatial,
            material: {STEEL},
            section: {section},
            geometry: (points: [[0.0, 0.0, 0.0], {vec(d)}], elements_per_segment: 4, orientation: Some((1.0, 0.0, 0.0))),
            frame: Clamped(node: 0),
            boundary: [(node: 4, dof: Ux), (node: 4, dof: Uy), (node: 4, dof: Uz)],
            normal_modes: 2,
            damping: {damping(body)},
         )),
         markers: [{marker(a, (0.0, 0.0, 0.0))}, {marker(b, d)}]),'''


def quarter_chassis(c):
    p = corner_points(c)
    plus, minus = pivots(c)
    points = {"Pf": plus, "Pr": minus, **{n: p[n] for n in ["L0", "T0", "S0", "E"]}}
    markers = [marker("cg", (0.0, 0.0, 0.0))] + [marker(f"{n}_{c}", sub(v, CHASSIS_CG)) for n, v in points.items()]
    inertia = ", ".join(f"{i * QUARTER_CHASSIS_MASS / 1260.0:.4f}" for i in (130.0, 1620.0, 1670.0))
    return f'''        // 2.7: the quarter chassis, 327.03 kg; on its vertical slider only its mass matters (the
        // inertia is the chassis's of 2.2 scaled by the mass, CHOSEN). Markers at their 2.3 points.
        (name: "chassis", origin: {vec(CHASSIS_CG)},
         model: Rigid(mass: {QUARTER_CHASSIS_MASS}, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([{inertia}])),
         markers: [{", ".join(markers)}]),'''


def suspension_joints(c):
    return '''        (name: "sled_slider", kind: Prismatic(axis: [1.0, 0.0, 0.0]), body1: "ground", marker1: "cg0", body2: "sled", marker2: "cg"),
        // 2.7: the quarter chassis on a prismatic joint along z.
        (name: "chassis_slider", kind: Prismatic(axis: [0.0, 0.0, 1.0]), body1: "sled", marker1: "cg", body2: "chassis", marker2: "cg"),
''' + corner_joints(c)


def corner_joints(c):
    """The joints of one corner's beam bodies (2.8), shared by scenes B and C."""
    p = corner_points(c)
    rod = unit(sub(p["T1"], p["T0"]))
    normal = tuple(round(v, 9) + 0.0 for v in unit(cross((1.0, 0.0, 0.0), rod)))
    return f'''        // 2.8: the A-arm spherical to the chassis at P+ and P- (for a rigid arm together a
        // revolute about the pivot axis plus one redundant equation), spherical to the carrier at B.
        (name: "aarm_front_pivot_{c}", kind: Spherical, body1: "chassis", marker1: "Pf_{c}", body2: "aarm_{c}", marker2: "Pf"),
        (name: "aarm_rear_pivot_{c}", kind: Spherical, body1: "chassis", marker1: "Pr_{c}", body2: "aarm_{c}", marker2: "Pr"),
        (name: "ball_joint_{c}", kind: Spherical, body1: "aarm_{c}", marker1: "B", body2: "carrier_{c}", marker2: "B"),
        // 2.8: the leaf link revolute about x at L0, spherical at U.
        (name: "leaf_link_pivot_{c}", kind: Revolute(axis: Some([1.0, 0.0, 0.0])), body1: "chassis", marker1: "L0_{c}", body2: "leaf_link_{c}", marker2: "L0"),
        (name: "leaf_link_ball_{c}", kind: Spherical, body1: "leaf_link_{c}", marker1: "U", body2: "carrier_{c}", marker2: "U"),
        // 2.8: the tie rod universal at T0 (chassis x, then the normal to x and the rod), spherical at T1.
        (name: "tie_rod_inner_{c}", kind: Universal(axis1: [1.0, 0.0, 0.0], axis2: {vec(normal)}), body1: "chassis", marker1: "T0_{c}", body2: "tie_rod_{c}", marker2: "T0"),
        (name: "tie_rod_outer_{c}", kind: Spherical, body1: "tie_rod_{c}", marker1: "T1", body2: "carrier_{c}", marker2: "T1"),'''


SUSPENSION_SENSORS = '''        (name: "chassis_z", kind: Position(body: "chassis", marker: "cg", component: Z)),
        (name: "wheel_fl_z", kind: Position(body: "carrier_fl", marker: "W", component: Z)),
        (name: "tyre_fl", kind: ElementForce(force: "tyre_fl")),
        (name: "strut_fl", kind: ElementForce(force: "strut_fl")),
        (name: "leaf_fl", kind: ElementForce(force: "leaf_fl")),
        // 2.11: the elastic displacement of B and S1 normal to the arm plane, in the arm's frame
        // (the marker's position in it minus the undeformed one; 0 for a rigid arm).
        (name: "aarm_fl_deflection", kind: Position(body: "aarm_fl", marker: "B", component: Z, frame: Some("aarm_fl")), displacement: true),
        (name: "aarm_fl_s1_deflection", kind: Position(body: "aarm_fl", marker: "S1", component: Z, frame: Some("aarm_fl")), displacement: true),'''


def corner_bodies(c):
    """One corner's bodies (2.8): the A-arm beam frame, the carrier + wheel, the leaf link and
    the tie rod; shared by scenes B and C (the corner is written once, mirrored by
    corner_points as 2.1 and 3.1 say)."""
    return [
        aarm_beam(c),
        carrier(c),
        straight_beam(f"leaf_link_{c}", "leaf_link", c, "L0", "U", LEAF_LINK_SECTION,
                      "2.8 leaf-spring link L0-U: flat leaf 60 x 12 mm, 4 elements, 1.903 kg (DERIVED)"),
        straight_beam(f"tie_rod_{c}", "tie_rod", c, "T0", "T1", TIE_ROD_SECTION,
                      "2.8 tie rod T0-T1: tube OD 22 x 3 mm, 4 elements, 0.540 kg (DERIVED)"),
    ]


def suspension_scene():
    c = "fl"
    step_x = FRONT_LEFT["W"][0] + SLED_SPEED * DROP_TIME
    bodies = [
        f'''        // 2.10 (CHOSEN way of writing the moving road): a sled on a prismatic x joint carries the
        // corner at {SLED_SPEED} m/s over the fixed road; nothing acts on it along x (vertical tyre, no
        // longitudinal force), so its speed stays constant; its mass (1 kg, CHOSEN) carries no load.
        (name: "sled", origin: {vec(CHASSIS_CG)},
         model: Rigid(mass: 1.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([1.0, 1.0, 1.0])),
         markers: [(name: "cg", position: [0.0, 0.0, 0.0])]),''',
        quarter_chassis(c),
    ] + corner_bodies(c)
    header = f"""// Generated by models/generate_iltis.py from docs/scenes.md 2.1-2.11 (edit the script, not this file).
// Scene B, the Iltis suspension (thesis ch. 2, second example): the front-left corner of the IAVSD
// Iltis benchmark (S9: ovankerm/IAVSD_ILTIS, commit 18c4286) with a quarter chassis (327.03 kg) on a
// vertical slider, the carrier + wheel rigid (57.35 kg), and the A-arm, the leaf-spring link and
// the tie rod as beam bodies (2.8) that run rigid with their FE mass properties (the "thesis
// configuration", 2.8) unless switched flexible: `--set bodies.aarm_fl.flexible=true`, then
// `leaf_link_fl`, `tie_rod_fl` (k = 1, 2, 3). Structural damping C = beta K (2.9). Strut, leaf
// element and tyre as in models/iltis_vehicle_benchmark.ron (2.4, 2.5); the leaf element acts on
// the carrier's U (the leaf link's U is joined to it by the spherical joint).
// The 20 cm drop (2.10): the road under the wheel is 0 until the wheel centre reaches
// x = {step_x:g} m at t = {DROP_TIME} s, -{DROP_HEIGHT} m after (a Table step; the corner rides its sled at {SLED_SPEED} m/s).
// Checks (2.7, thesis configuration, rigid): chassis 9.818 mm below nominal (z = 0.570 m), tyre
// 3853.55 N, leaf -3075.97 N, strut -338.28 N. Static start, 5 s, h = 1 ms (2.10)."""
    return f'''{header}
(
    name: "iltis suspension",
    description: "scene B: the Iltis suspension, one front corner with a quarter chassis on a vertical slider, the 20 cm drop at 0.5 s",
    dim: Spatial,
    gravity: [0.0, 0.0, -9.81],
    initial_velocity: {vec((SLED_SPEED, 0.0, 0.0))},
    ground: [(name: "cg0", position: {vec(CHASSIS_CG)})],
    bodies: [
{chr(10).join(bodies)}
    ],
    joints: [
{suspension_joints(c)}
    ],
    forces: [
{forces(c, "road", "Vertical", 0.0)}
    ],
    roads: [
        Road(name: "road", profile: Table(x: [{number(step_x)}, {number(step_x)}], z: [0.0, {number(-DROP_HEIGHT)}])),
    ],
    sensors: [
{SUSPENSION_SENSORS}
    ],
    solver: (step: 1e-3, duration: 5.0, output_interval: Some(0.005), initial_state: StaticEquilibrium),
)
'''


# ---------------------------------------------------------------------------------------------
# Scene C (docs/scenes.md 3.4-3.7): the whole vehicle in the thesis configuration, the corner of
# scene B (corner_bodies, corner_joints, forces) at the four positions of 3.1, the chassis free.
# ---------------------------------------------------------------------------------------------

# 3.6: every body moves forward at 5 m/s [T]; 8 s [T]; h = 1 ms (CHOSEN).
VEHICLE_SPEED = 5.0
# 3.5 (CHOSEN): (s, height) breakpoints of the ramp-and-steps profile, s the distance the
# front axle travels; a repeated s is a step (down only). The road's x is the wheel centre's,
# so the profile is written at x = x_F + s (the front wheels start at s = 0; the rear axle sees
# it 2.017 m later).
RAMP_AND_STEPS = [(3.0, 0.0), (4.0, 0.10), (10.0, 0.10), (10.0, 0.0), (20.0, 0.0), (20.0, -0.10)]


def vehicle_chassis():
    """The chassis of 2.2 / 3.1 with the points of every corner's beam bodies (2.8: the A-arm
    pivots P+ and P-, L0, T0) and force elements (S0, E), relative to its centre of mass."""
    markers = [marker("cg", (0.0, 0.0, 0.0))]
    for c in ["fl", "fr", "rl", "rr"]:
        p = corner_points(c)
        plus, minus = pivots(c)
        points = {"Pf": plus, "Pr": minus, **{n: p[n] for n in ["L0", "T0", "S0", "E"]}}
        markers += [marker(f"{n}_{c}", sub(v, CHASSIS_CG)) for n, v in points.items()]
    return f'''        (name: "chassis", origin: {vec(CHASSIS_CG)},
         // 2.2: 1260 kg at the centre of mass, Ixx 130, Iyy 1620, Izz 1670 kg m^2 [S9 Jeep.mbs].
         model: Rigid(mass: 1260.0, center_of_mass: [0.0, 0.0, 0.0], inertia: Diagonal([130.0, 1620.0, 1670.0])),
         markers: [
            {(","+chr(10)+"            ").join(markers)},
         ]),'''


VEHICLE_SENSORS = SENSORS + '''
        // 3.7 / 2.11: the front-left A-arm's deflection, the elastic displacement of B (and S1)
        // normal to the arm plane in the arm's frame (0 while the arm is rigid).
        (name: "aarm_fl_deflection", kind: Position(body: "aarm_fl", marker: "B", component: Z, frame: Some("aarm_fl")), displacement: true),
        (name: "aarm_fl_s1_deflection", kind: Position(body: "aarm_fl", marker: "S1", component: Z, frame: Some("aarm_fl")), displacement: true),'''


def vehicle_scene():
    corners = ["fl", "fr", "rl", "rr"]
    bodies = [vehicle_chassis()] + [b for c in corners for b in corner_bodies(c)]
    xs = ", ".join(number(round(X_FRONT + s, 9)) for s, _ in RAMP_AND_STEPS)
    zs = ", ".join(number(z) for _, z in RAMP_AND_STEPS)
    header = """// Generated by models/generate_iltis.py from docs/scenes.md 2.1-3.7 (edit the script, not this file).
// Scene C, the Iltis vehicle (thesis ch. 2, third example) in the thesis configuration (3.4): the
// IAVSD Iltis benchmark (S9: ovankerm/IAVSD_ILTIS, commit 18c4286) with the chassis free (6 DOF)
// and at every corner c in fl, fr, rl, rr the corner of scene B (models/iltis_suspension.ron,
// 2.8): carrier + wheel rigid, and the A-arm, leaf-spring link and tie rod as beam bodies that run
// rigid with their FE mass properties unless switched flexible, `--set bodies.aarm_c.flexible=true`
// (then leaf_link_c, tie_rod_c; 3.4 switches them corner by corner FL, FR, RL, RR, each in that
// order). Right corners mirrored in y, rear corners in x about the rear axle (2.1, 3.1; the
// A-arm's strut bracket and its pivot "Pf" on the strut's side). Total mass 1523.17 kg (3.4).
// Structural damping C = beta K (2.9). Strut, leaf element and tyre as in
// models/iltis_vehicle_benchmark.ron (2.4, 2.5), vertical point contact; lateral tyre dampers
// C_alpha / V = 41641 / 5 and 40162 / 5 N s/m (3.4).
// Road (3.5, CHOSEN): the ramp and steps at s = x - 0.970 m: flat to 3 m, ramp to +0.10 m at 4 m,
// step down to 0 at 10 m and to -0.10 m at 20 m, the same under both tracks.
// Checks (3.4, all bodies rigid): chassis 7.373 mm below nominal (z = 0.570 m), pitch 0.1472 deg
// nose down, tyres 3855.29 / 3615.83 N, leaf elements -3077.46 / -2893.55 N, struts -338.88 /
// -246.58 N. Static start, every body at 5 m/s, 8 s, h = 1 ms (3.6)."""
    return f'''{header}
(
    name: "iltis vehicle",
    description: "scene C: the Iltis vehicle, thesis configuration (A-arms, leaf links and tie rods as beam bodies, rigid unless switched flexible), 5 m/s over the ramp and steps",
    dim: Spatial,
    gravity: [0.0, 0.0, -9.81],
    initial_velocity: {vec((VEHICLE_SPEED, 0.0, 0.0))},
    ground: [(name: "cg0", position: {vec(CHASSIS_CG)})],
    bodies: [
{chr(10).join(bodies)}
    ],
    joints: [
        (name: "chassis_float", kind: Free, body1: "ground", marker1: "cg0", body2: "chassis", marker2: "cg"),
{chr(10).join(corner_joints(c) for c in corners)}
    ],
    forces: [
{chr(10).join(forces(c, "road", "Vertical", VEHICLE_SPEED) for c in corners)}
    ],
    roads: [
        Road(name: "road", profile: Table(x: [{xs}], z: [{zs}])),
    ],
    sensors: [
{VEHICLE_SENSORS}
    ],
    solver: (step: 1e-3, duration: 8.0, output_interval: Some(0.005), initial_state: StaticEquilibrium),
)
'''


def main():
    flat = '        Road(name: "road", profile: Flat),'
    bump = ('        // S9 GroundContact.c: h(x) = 0.1 (1 - cos(2 pi (x - 0.97) / 5)) on [0.97, 5.97] m,\n'
            '        // the same under both tracks (in phase); the front wheels start at its foot. CHOSEN:\n'
            '        // the bump starts 1 mm ahead of them (0.971 m), so that the static start is on flat\n'
            '        // road: with a wheel exactly at the foot the equilibrium is bounded only one way\n'
            '        // (x <= 0.97), and the two formulations settled 0.57 mm apart along it.\n'
            '        Road(name: "road", profile: CosineBump(start: 0.971, length: 5.0, height: 0.2)),')
    bench = scene(
        "iltis vehicle benchmark",
        "scene C0: the IAVSD Iltis benchmark vehicle (S9 masses, massless links as constraints), at rest on a flat road",
        COMMON + """
// Checks (scenes.md 2.6, 3.2): nominal loads at the nominal position (solver.initial_state = Given):
// leaf -2728.9 N, strut -128.0 N, tyres 3829.5 / 3593.5 N; the static equilibrium (this file's
// start): chassis -7.083 mm (z = 0.5629166 m), pitch 0.1465 deg nose down, tyres 3831.31 / 3591.91 N,
// struts -335.29 / -241.64 N, leaf elements -3068.62 / -2885.51 N [S9 2_Equilibrium_Report.txt].
// Run: 1 s at rest from the equilibrium (nothing may move); h = 1 ms CHOSEN (scenes.md 3.6).""",
        flat, "Vertical", (0.0, 0.0, 0.0),
        "(step: 1e-3, duration: 1.0, output_interval: Some(0.01), initial_state: StaticEquilibrium)")
    bump_scene = scene(
        "iltis bump",
        "scene C0 over the benchmark cosine bump, in phase, from static equilibrium at 5 m/s",
        COMMON + """
// The benchmark cosine bump (scenes.md 3.2, S9 InPhaseCosine_5ms_*.res): 0.20 m high, 5 m long,
// profile-normal radial tyre contact as S9 GroundContact.c; start from the static equilibrium with
// every body moving forward at initial_velocity (5 m/s; `--set initial_velocity.0=10` for the
// 10 m/s run), no longitudinal tyre force, 2.5 s. S9 extremes at 5 m/s: centre-of-mass rise
// 127.8 mm at 0.725 s, pitch -6.35 deg (0.538 s) and +7.64 deg (1.033 s), front tyre 1300.5 to
// 6202.4 N, rear 1360.1 to 5664.2 N; at 10 m/s the wheels lift off and the rise peaks near 314.1 mm.
// S9 adds Calspan lateral tyre forces, which the in-phase bump does excite (the contact points
// move sideways as the suspension travels): here the linear lateral damper of scenes.md 3.4,
// C_alpha / V = 41641 / 5 and 40162 / 5 N s/m at the wheel centres. The damping is written for
// 5 m/s; the 10 m/s run of the report and tests sets it to C_alpha / 10.""",
        bump, "ProfileNormal", (5.0, 0.0, 0.0),
        "(step: 1e-3, duration: 2.5, output_interval: Some(0.005), initial_state: StaticEquilibrium)")
    for path, text in [("models/iltis_vehicle_benchmark.ron", bench), ("models/iltis_bump.ron", bump_scene),
                       ("models/iltis_suspension.ron", suspension_scene()),
                       ("models/iltis_vehicle.ron", vehicle_scene())]:
        with open(path, "w") as f:
            f.write(text)
        print("wrote", path)


if __name__ == "__main__":
    main()
