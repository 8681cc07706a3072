#!/usr/bin/env python3
"""Spherical (or cylindrical) cavity expansion in the HJC concrete: the resistance the material
model itself offers.

What it computes
----------------
A spherical cavity of initial radius a0 is expanded at a constant wall speed V in an unbounded
medium (spherical symmetry, 1-D Lagrangian finite differences, von Neumann-Richtmyer / HEMP
staggered grid). Once the expansion is self-similar (a/a0 >= ~15) the radial stress on the cavity
wall, sigma_r(a) (compression positive), is the cavity-expansion resistance of Forrestal's
penetration theory: at low V it is the quasi-static "S f_c" term, and its growth with V shows the
inertial "N rho V^2" part. The concrete is the Holmquist-Johnson-Cook model exactly as coded in
src/materials/hjc.rs (f_c rule `Hjc::from_fc`, EOS with crushing and lock, strength with the rate
term, damage), updated per zone in the order of src/cpu/concrete.rs. This is an independent check,
in Python/numpy, of the resistance the HJC model offers, free of SPH, contact and projectile.

With --geometry cylindrical the cavity is a cylinder in plane strain (per unit length, no axial
strain): the limit of an infinitely slender nose, which opens the target sideways only. Forrestal's
theory uses the spherical one for every nose; a real nose lies between the two.

Usage
-----
    python3 scripts/cavity_expansion.py                       # HJC, f_c 34.7 MPa, rate term on
    python3 scripts/cavity_expansion.py --no-rate             # ... rate term off
    python3 scripts/cavity_expansion.py --both-rates          # both, one table
    python3 scripts/cavity_expansion.py --check               # verification only (see below)
    python3 scripts/cavity_expansion.py --geometry cylindrical [...]   # any of these, cylindrical
    python3 scripts/cavity_expansion.py --shots data/forrestal1994.csv \
        --speeds 10,25,50,100,150,200,300,400,500,650,800     # depths of a rigid ogive (below)
    options: --fc PA --density KG_M3 --speeds 25,50,100,200 --a-end 25 --merge-frac 0.01
             --set KEY=VALUE (override one constant of the f_c rule's set, e.g. mu_lock=0.13)

Depths (--shots)
----------------
For each measured shot, the wall stress at the listed speeds (at the shot's f_c) becomes the
normal stress sigma_n(V_n) on a rigid, frictionless CRH ogive, V_n = V cos(phi) being the normal
speed of each point of the nose (Forrestal's method); sigma_n below the slowest speed is taken as
the slowest one's (the quasi-static limit: list a slow speed first). The axial force over the
nose gives the resistance R(V); the projectile then crosses Forrestal's crater (a force growing
linearly over 4a to its tunnel value) and the tunnel: P = 4a + int_0^V1 m V dV / (pi a^2 R(V)).
Printed beside the measured depth and Forrestal's equation: the depth the concrete model itself
predicts, free of SPH, contact and the projectile's deformation.

Verification (--check)
----------------------
0. The Python HJC functions reproduce the numbers of the unit tests in hjc.rs.
1. Linear elastic medium, small expansion: sigma_r(a) = 4 G u_a / a0 (compression positive).
2. Elastic-perfectly plastic (von Mises, constant Y, p = K mu) expanded to a/a0 = 25 at a low
   speed: Hill's limit pressure p = (2Y/3) [1 + ln(E / (3 (1 - nu) Y))]; cylindrical (with
   --geometry cylindrical: 1. becomes sigma_r(a) = 2 G u_a / a0): Hill's incompressible
   p = k [1 + ln(G/k)], k = Y/sqrt(3), checked at nu = 0.495.
3. The rigid-ogive integration of --shots: projected area, Forrestal's N, his closed-form depth.

Scheme
------
Nodes carry r and u (radial velocity, at half steps); zones carry the mass, p, the deviators s_r
and s_theta (the third is -s_r - s_theta: s_phi = s_theta = -s_r/2 in the sphere, s_z in the
cylinder), mu_max, D, eps_p and the artificial viscosity q. The node equation of motion is the
exact integral of  rho du/dt = d(sigma_r)/dr + k (sigma_r - sigma_theta)/r  (k = 2 spherical, 1
cylindrical) over the node's control volume (the two half zones, weight r^k) for
piecewise-constant zone stresses.
Zones that become thinner than `merge_frac` times their radius (the material near the wall is
squeezed into thin shells as the cavity grows: r^k dr is roughly conserved) are merged with their
thinner neighbour (mass-weighted state), which keeps the time step proportional to a.
The wall stress is reported two ways: the innermost zone's sigma_r (incl. q), and the traction the
prescribed wall node needs, from the equilibrium of its half zone (the innermost zone's stress
carried to r = a; first-order in the zone thickness). The second is the better estimate.
"""

import argparse
import math
import sys
import time
from dataclasses import dataclass, replace

import numpy as np

# ---------------------------------------------------------------------------------------------
# HJC, transcribed from src/materials/hjc.rs (vectorised over zones; float64 instead of f32)
# ---------------------------------------------------------------------------------------------

LOCK_NEWTON_STEPS = 4          # Newton steps for the lock strain
POW_BASE_FLOOR = 1.0e-30       # smallest base handed to pow
FAILURE_STRAIN_FLOOR = 1.0e-20  # floor of the failure strain
F32_MIN_POSITIVE = 1.1754944e-38  # f32::MIN_POSITIVE, used to guard divisions as in Rust


@dataclass(frozen=True)
class Hjc:
    """HJC constants, SI (Pa, kg/m^3)."""
    density: float
    shear_modulus: float
    a: float
    b: float
    n: float
    c: float
    s_max: float
    fc: float
    t: float            # tensile strength T (positive)
    eps_rate_ref: float
    ef_min: float
    d1: float
    d2: float
    p_crush: float
    mu_crush: float
    k1: float
    k2: float
    k3: float
    p_lock: float
    mu_lock: float


def reference_48mpa():
    """The 48 MPa reference set of Holmquist, Johnson & Cook (1993)."""
    return Hjc(density=2440.0, shear_modulus=14.86e9, a=0.79, b=1.60, n=0.61, c=0.007,
               s_max=7.0, fc=48.0e6, t=4.0e6, eps_rate_ref=1.0, ef_min=0.01, d1=0.04, d2=1.0,
               p_crush=16.0e6, mu_crush=0.001, k1=85.0e9, k2=-171.0e9, k3=208.0e9,
               p_lock=0.8e9, mu_lock=0.10)


GRAIN_DENSITY = 2684.0  # kg/m^3, the reference set's rho0 (1 + mu_lock), as in hjc.rs


def from_fc(fc, density):
    """The f_c rule: E = 4730 sqrt(f_c[MPa]) MPa, nu = 0.2, G = E/(2(1+nu)),
    K_el = E/(3(1-2nu)), P_crush = f_c/3, mu_crush = P_crush/K_el, T = 0.62 sqrt(f_c[MPa]) MPa,
    mu_lock = GRAIN_DENSITY/rho0 - 1; everything else from the reference set."""
    fc_mpa = fc / 1.0e6
    youngs = 4730.0e6 * math.sqrt(fc_mpa)
    nu = 0.2
    shear = youngs / (2.0 * (1.0 + nu))
    bulk_elastic = youngs / (3.0 * (1.0 - 2.0 * nu))
    p_crush = fc / 3.0
    return replace(reference_48mpa(), density=density, shear_modulus=shear, fc=fc,
                   t=0.62e6 * math.sqrt(fc_mpa), p_crush=p_crush,
                   mu_crush=p_crush / bulk_elastic, mu_lock=GRAIN_DENSITY / density - 1.0)


def dense_pressure(h, mu_bar):
    """Fully dense curve p = K1 mu_bar + K2 mu_bar^2 + K3 mu_bar^3."""
    return (h.k1 + (h.k2 + h.k3 * mu_bar) * mu_bar) * mu_bar


def dense_slope(h, mu_bar):
    """dp/dmu_bar = K1 + 2 K2 mu_bar + 3 K3 mu_bar^2."""
    return h.k1 + (2.0 * h.k2 + 3.0 * h.k3 * mu_bar) * mu_bar


def lock_strain(h):
    """mu_plock: root of the dense curve = P_lock, mu_plock = mu_lock + (1 + mu_lock) mu_bar."""
    mu_bar = h.p_lock / h.k1
    for _ in range(LOCK_NEWTON_STEPS):
        slope = max(dense_slope(h, mu_bar), 0.1 * h.k1)
        mu_bar -= (dense_pressure(h, mu_bar) - h.p_lock) / slope
    return h.mu_lock + (1.0 + h.mu_lock) * mu_bar


def crush_envelope(h, m, k_el, mu_plock):
    """Loading pressure p_env and unloading modulus K_unload at a largest compression m:
    p_env = K_el m up to mu_crush, then the line (mu_crush, P_crush) -> (mu_plock, P_lock);
    K_unload = K_el + (K1 - K_el) F, F = clamp((m - mu_crush)/(mu_plock - mu_crush), 0, 1)."""
    span = max(mu_plock - h.mu_crush, F32_MIN_POSITIVE)
    frac = np.clip((m - h.mu_crush) / span, 0.0, 1.0)
    crushing = h.p_crush + (h.p_lock - h.p_crush) * frac
    p_env = np.where(m <= h.mu_crush, k_el * m, crushing)
    return p_env, k_el + (h.k1 - k_el) * frac


def plastic_volumetric_strain(h, mu_max, k_el, mu_plock):
    """mu_p = m - p_env(m)/K_unload(m), m = mu_max held in [mu_crush, mu_plock]."""
    m = np.minimum(np.maximum(mu_max, h.mu_crush), mu_plock)
    p_env, k_unload = crush_envelope(h, m, k_el, mu_plock)
    return m - p_env / k_unload


def pressure(h, mu, mu_max, damage, mu_plock=None):
    """Three-part HJC EOS with compaction history. Returns (p, new mu_max, d_mu_p, tangent).
    m = max(mu, mu_max); m < mu_plock: p = p_env(m) - K_unload(m)(m - mu);
    m >= mu_plock: p = dense curve of mu_bar = (mu - mu_lock)/(1 + mu_lock);
    tension cut-off p >= -T (1 - D). `mu_plock` may be passed precomputed (= lock_strain(h))."""
    k_el = h.p_crush / h.mu_crush
    if mu_plock is None:
        mu_plock = lock_strain(h)
    new_max = np.maximum(mu, mu_max)

    p_env, k_unload = crush_envelope(h, np.minimum(new_max, mu_plock), k_el, mu_plock)
    crushing_slope = (h.p_lock - h.p_crush) / max(mu_plock - h.mu_crush, F32_MIN_POSITIVE)
    p_crushable = p_env - k_unload * (new_max - mu)
    k_crushable = np.maximum(k_unload, crushing_slope)

    mu_bar = (mu - h.mu_lock) / (1.0 + h.mu_lock)
    locked = new_max >= mu_plock
    p = np.where(locked, dense_pressure(h, mu_bar), p_crushable)
    tangent = np.where(locked, dense_slope(h, mu_bar) / (1.0 + h.mu_lock), k_crushable)

    d_mu_p = np.maximum(plastic_volumetric_strain(h, new_max, k_el, mu_plock)
                        - plastic_volumetric_strain(h, mu_max, k_el, mu_plock), 0.0)
    d = np.clip(damage, 0.0, 1.0)
    return np.maximum(p, -h.t * (1.0 - d)), new_max, d_mu_p, np.maximum(tangent, k_el)


def rate_factor(h, eps_rate):
    """1 + C ln(eps_rate*), eps_rate* = max(eps_rate/eps_rate_ref, 1)."""
    return 1.0 + h.c * np.log(np.maximum(eps_rate / h.eps_rate_ref, 1.0))


def yield_stress(h, p, damage, eps_rate):
    """sigma_y = f_c sigma*, P* = p/f_c:
    P* >= 0: sigma* = min([A(1-D) + B P*^N] rate, S_max);
    P* <  0: sigma* = max(A (1 + p/T)(1-D) rate, 0)."""
    d = np.clip(damage, 0.0, 1.0)
    rate = rate_factor(h, eps_rate)
    p_star = p / h.fc
    hardening = h.b * np.maximum(p_star, POW_BASE_FLOOR) ** h.n
    compressive = np.minimum((h.a * (1.0 - d) + hardening) * rate, h.s_max)
    tensile = np.maximum(h.a * (1.0 + p / h.t) * (1.0 - d) * rate, 0.0)
    return h.fc * np.where(p_star >= 0.0, compressive, tensile)


def damage_increment(h, p, d_eps_p, d_mu_p):
    """dD = (d_eps_p + d_mu_p) / max(D1 (P* + T*)^D2, EF_min)."""
    base = (p + h.t) / h.fc
    eps_f = np.maximum(np.maximum(h.d1 * np.maximum(base, POW_BASE_FLOOR) ** h.d2, h.ef_min),
                       FAILURE_STRAIN_FLOOR)
    return (d_eps_p + d_mu_p) / eps_f


def sound_speed(h, tangent):
    """c = sqrt((dp/dmu + 4G/3)/rho0)."""
    return np.sqrt(np.maximum((tangent + 4.0 / 3.0 * h.shear_modulus) / h.density, 0.0))


# ---------------------------------------------------------------------------------------------
# Materials as seen by the solver
# ---------------------------------------------------------------------------------------------

class HjcMaterial:
    """HJC with the rate term on or off (off: the strain rate handed to the strength is 0)."""

    def __init__(self, h, use_rate=True):
        self.h = h
        self.use_rate = use_rate
        self.rho0 = h.density
        self.shear = h.shear_modulus
        self.mu_plock = lock_strain(h)
        # Fastest wave speed the EOS can give for any sensible compression (for the domain size).
        self.c_max = float(sound_speed(h, max(h.p_crush / h.mu_crush, h.k1)))

    def eos(self, mu, mu_max, damage):
        return pressure(self.h, mu, mu_max, damage, self.mu_plock)

    def yield_stress(self, p, damage, eps_rate):
        return yield_stress(self.h, p, damage, eps_rate if self.use_rate else 0.0 * eps_rate)

    def damage_increment(self, p, d_eps_p, d_mu_p):
        return damage_increment(self.h, p, d_eps_p, d_mu_p)

    def sound_speed(self, tangent):
        return sound_speed(self.h, tangent)


class ElasticPlastic:
    """Linear elastic EOS p = K mu, shear modulus G, von Mises with constant Y (inf: elastic)."""

    def __init__(self, youngs, nu, density, y=math.inf):
        self.rho0 = density
        self.shear = youngs / (2.0 * (1.0 + nu))
        self.bulk = youngs / (3.0 * (1.0 - 2.0 * nu))
        self.y = y
        self.c_max = math.sqrt((self.bulk + 4.0 / 3.0 * self.shear) / density)

    def eos(self, mu, mu_max, damage):
        return self.bulk * mu, np.maximum(mu, mu_max), 0.0 * mu, np.full_like(mu, self.bulk)

    def yield_stress(self, p, damage, eps_rate):
        return np.full_like(p, self.y)

    def damage_increment(self, p, d_eps_p, d_mu_p):
        return 0.0 * p

    def sound_speed(self, tangent):
        return np.sqrt((tangent + 4.0 / 3.0 * self.shear) / self.rho0)


# ---------------------------------------------------------------------------------------------
# 1-D spherical Lagrangian solver
# ---------------------------------------------------------------------------------------------

Q_LINEAR = 0.06     # artificial viscosity, linear coefficient (times c)
Q_QUADRATIC = 1.5   # artificial viscosity, quadratic coefficient


@dataclass(frozen=True)
class Geometry:
    """The cavity's symmetry. k hoop directions (2: spherical; 1: cylindrical, in plane strain,
    per unit length); volumes and node areas carry the weight `scale` r^k."""
    name: str
    k: int
    scale: float

    def shell_volume(self, r_in, r_out):
        return self.scale / (self.k + 1) * (r_out ** (self.k + 1) - r_in ** (self.k + 1))


SPHERICAL = Geometry("spherical", 2, 4.0 * math.pi)
CYLINDRICAL = Geometry("cylindrical", 1, 2.0 * math.pi)
GEOMETRIES = {g.name: g for g in (SPHERICAL, CYLINDRICAL)}


def make_grid(a0, dr0, growth, r_outer):
    """Node radii from a0 outward: zone sizes dr0 * growth^k until r_outer is passed."""
    n = int(math.ceil(math.log(1.0 + (r_outer - a0) * (growth - 1.0) / dr0) / math.log(growth)))
    return a0 + np.concatenate(([0.0], np.cumsum(dr0 * growth ** np.arange(max(n, 2)))))


class Zones:
    """Zone state (arrays of length N) and node state (length N + 1)."""

    FIELDS = ("mass", "p", "q", "s_r", "s_t", "mu_max", "damage", "eps_p", "tangent", "tr")

    def __init__(self, r, mat, geometry):
        self.r = r.copy()
        self.u = np.zeros_like(r)
        n = len(r) - 1
        self.mass = mat.rho0 * geometry.shell_volume(r[:-1], r[1:])
        for name in self.FIELDS[1:]:
            setattr(self, name, np.zeros(n))
        self.tangent = mat.eos(np.zeros(n), np.zeros(n), np.zeros(n))[3] * np.ones(n)

    def merge(self, j):
        """Merge zones j and j+1 (remove node j+1); state mass-weighted, tangent the larger."""
        m1, m2 = self.mass[j], self.mass[j + 1]
        for name in ("p", "q", "s_r", "s_t", "mu_max", "damage", "eps_p", "tr"):
            arr = getattr(self, name)
            arr[j] = (m1 * arr[j] + m2 * arr[j + 1]) / (m1 + m2)
        self.tangent[j] = max(self.tangent[j], self.tangent[j + 1])
        self.mass[j] = m1 + m2
        for name in self.FIELDS:
            setattr(self, name, np.delete(getattr(self, name), j + 1))
        self.r = np.delete(self.r, j + 1)
        self.u = np.delete(self.u, j + 1)


def merge_thin_zones(z, merge_frac):
    """Merge every zone thinner than merge_frac * (its mid radius) with its thinner neighbour."""
    merges = 0
    while True:
        dr = z.r[1:] - z.r[:-1]
        thin = np.flatnonzero(dr < merge_frac * 0.5 * (z.r[1:] + z.r[:-1]))
        if thin.size == 0 or len(dr) < 3:
            return merges
        j = thin[0]
        if j > 0 and (j == len(dr) - 1 or dr[j - 1] < dr[j + 1]):
            j -= 1
        z.merge(j)
        merges += 1


def wall_stresses(z, k):
    """Compression-positive wall stress: (innermost zone sigma_r incl. q, wall traction).
    Wall traction from the half-zone balance of the (unaccelerated) wall node:
    0 = a^k (sigma_r0 - sigma_wall) + (sigma_r - sigma_theta)_0 (r_c0^k - a^k)."""
    sig_r0 = z.s_r[0] - z.p[0] - z.q[0]
    a = z.r[0]
    rc = 0.5 * (z.r[0] + z.r[1])
    sig_wall = sig_r0 + (z.s_r[0] - z.s_t[0]) * (rc ** k - a ** k) / a ** k
    return -sig_r0, -sig_wall


def expand_cavity(mat, speed, a0=1.0e-3, a_end=25.0, dr0_frac=1.0 / 20.0, growth=1.02,
                  merge_frac=0.01, cfl=0.5, geometry=SPHERICAL):
    """Expand a cavity of radius a0 at wall speed `speed` until a = a_end * a0.
    Returns a dict with the history (a/a0, zone and wall stresses) and the final state."""
    t_end = (a_end - 1.0) * a0 / speed
    r_outer = a0 + 1.5 * mat.c_max * t_end + 2.0 * a_end * a0
    k = geometry.k
    z = Zones(make_grid(a0, dr0_frac * a0, growth, r_outer), mat, geometry)
    n_initial = len(z.mass)
    g2 = 2.0 * mat.shear

    hist_a, hist_zone, hist_wall = [], [], []
    t, dt_prev, steps, merges = 0.0, 0.0, 0, 0
    while z.r[0] < a_end * a0:
        r = z.r
        dr = r[1:] - r[:-1]
        rc = 0.5 * (r[1:] + r[:-1])
        # Stresses, tension positive: sigma_r = s_r - p - q, sigma_r - sigma_theta = s_r - s_t.
        sig_r = z.s_r - z.p - z.q
        dev_diff = z.s_r - z.s_t

        # Time step: dt = C min dr / (Q + sqrt(Q^2 + c^2)), Q = c1 c + c2 dr |tr| (compressing).
        c = mat.sound_speed(z.tangent)
        qv = Q_LINEAR * c + Q_QUADRATIC * dr * np.maximum(-z.tr, 0.0)
        dt = cfl * np.min(dr / (qv + np.sqrt(qv * qv + c * c)))

        # Node forces (interior nodes): the integral of r^k (d(sigma_r)/dr + k(sigma_r -
        # sigma_theta)/r) over the two half zones around node i, exact for piecewise-constant
        # zone stresses.
        ri = r[1:-1]
        rik = ri ** k
        force = geometry.scale * (rik * (sig_r[1:] - sig_r[:-1])
                                  + dev_diff[:-1] * (rik - rc[:-1] ** k)
                                  + dev_diff[1:] * (rc[1:] ** k - rik))
        node_mass = 0.5 * (z.mass[1:] + z.mass[:-1])
        # Leapfrog: u^{n+1/2} = u^{n-1/2} + (F/m) (dt^{n-1/2} + dt^{n+1/2})/2.
        z.u[1:-1] += force / node_mass * 0.5 * (dt_prev + dt)
        z.u[0] = speed              # prescribed cavity wall
        z.u[-1] = 0.0               # far boundary fixed (no wave reaches it)
        r_new = r + dt * z.u
        r_mid = 0.5 * (r + r_new)

        # Strain rates at mid-step: eps_r = du/dr, eps_theta = u/r (zone averages); the third
        # direction is the second hoop direction (spherical) or the axis (plane strain, 0).
        eps_r = (z.u[1:] - z.u[:-1]) / (r_mid[1:] - r_mid[:-1])
        eps_t = (z.u[1:] + z.u[:-1]) / (r_mid[1:] + r_mid[:-1])
        tr = eps_r + k * eps_t
        dev_r = eps_r - tr / 3.0
        dev_t = eps_t - tr / 3.0
        dev_3 = (eps_t if k == 2 else 0.0) - tr / 3.0
        eq_rate = np.sqrt(2.0 / 3.0 * (dev_r * dev_r + dev_t * dev_t + dev_3 * dev_3))

        # Density from the new zone volume, then the EOS (new p, mu_max, d_mu_p) with old D.
        rho = z.mass / geometry.shell_volume(r_new[:-1], r_new[1:])
        mu = rho / mat.rho0 - 1.0
        p, mu_max, d_mu_p, tangent = mat.eos(mu, z.mu_max, z.damage)

        # Elastic trial deviator (s_r, s_t; the third is -s_r - s_t), yield with the new p and
        # the OLD damage, radial return. Spherical: s_t stays -s_r/2 and seq = 3/2 |s_r|.
        s_trial_r = z.s_r + g2 * dev_r * dt
        s_trial_t = z.s_t + g2 * dev_t * dt
        s_trial_3 = -s_trial_r - s_trial_t
        seq = np.sqrt(1.5 * (s_trial_r ** 2 + s_trial_t ** 2 + s_trial_3 ** 2))  # von Mises
        sy = mat.yield_stress(p, z.damage, eq_rate)
        over = seq > sy
        scale = np.divide(sy, seq, out=np.ones_like(seq), where=over)   # seq > sy >= 0 there
        d_eps_p = np.where(over, (seq - sy) / (3.0 * mat.shear), 0.0)
        z.s_r = s_trial_r * scale
        z.s_t = s_trial_t * scale
        z.eps_p = z.eps_p + d_eps_p
        z.damage = np.minimum(z.damage + mat.damage_increment(p, d_eps_p, d_mu_p), 1.0)
        z.p, z.mu_max, z.tangent, z.tr = p, mu_max, tangent, tr

        # Artificial viscosity on volumetrically compressing zones: jump = dr * tr (< 0),
        # q = rho (c1 c |jump| + c2 jump^2).
        jump = (r_new[1:] - r_new[:-1]) * np.minimum(tr, 0.0)
        z.q = rho * (Q_LINEAR * mat.sound_speed(tangent) * np.abs(jump) + Q_QUADRATIC * jump * jump)

        z.r = r_new
        t += dt
        dt_prev = dt
        steps += 1
        merges += merge_thin_zones(z, merge_frac)

        zone_s, wall_s = wall_stresses(z, k)
        hist_a.append(z.r[0] / a0)
        hist_zone.append(zone_s)
        hist_wall.append(wall_s)

    rc = 0.5 * (z.r[1:] + z.r[:-1])
    rho = z.mass / geometry.shell_volume(z.r[:-1], z.r[1:])
    return dict(a=np.array(hist_a), zone=np.array(hist_zone), wall=np.array(hist_wall),
                z=z, rc=rc, mu=rho / mat.rho0 - 1.0, steps=steps, merges=merges, t=t,
                n_initial=n_initial, r_outer=r_outer)


def window_mean(res, key, lo, hi):
    sel = (res["a"] >= lo) & (res["a"] <= hi)
    return float(np.mean(res[key][sel]))


def value_at(res, key, a_over_a0):
    """History value at a/a0 (linear interpolation)."""
    return float(np.interp(a_over_a0, res["a"], res[key]))


def summarise(res, a0=1.0e-3):
    """Averages over a/a0 in [15, 25], change [15,16] -> [24,25], zone extents in units of a."""
    z, rc = res["z"], res["rc"]
    a = z.r[0]
    plastic = np.flatnonzero(z.eps_p > 0.0)
    failed = np.flatnonzero(z.damage >= 1.0)
    # Contiguous fully-damaged layer from the wall.
    not_failed = np.flatnonzero(z.damage < 1.0)
    contiguous = (not_failed[0] if not_failed.size else len(rc)) - 1
    out = {}
    for key in ("wall", "zone"):
        out[key] = window_mean(res, key, 15.0, 25.0)
        out[key + "_change"] = window_mean(res, key, 24.0, 25.0) - window_mean(res, key, 15.0, 16.0)
    out["plastic"] = rc[plastic[-1]] / a if plastic.size else 0.0
    out["d1_outer"] = rc[failed[-1]] / a if failed.size else 0.0
    out["d1_contig"] = z.r[contiguous + 1] / a if contiguous >= 0 else 1.0
    out["mu_max"] = float(np.max(res["mu"]))
    out["mu_hist_max"] = float(np.max(z.mu_max))
    # Leading wave: outermost node moving faster than 1e-6 V, as a fraction of the outer radius
    # (must stay well below 1: the far boundary is never reached).
    moving = np.flatnonzero(np.abs(z.u) > 1.0e-6 * abs(z.u[0]))
    out["front"] = z.r[moving[-1]] / z.r[-1]
    return out


# ---------------------------------------------------------------------------------------------
# Verification
# ---------------------------------------------------------------------------------------------

def rel(got, want):
    return (got - want) / want


def check_transcription():
    """Numbers from the unit tests of src/materials/hjc.rs."""
    h = reference_48mpa()
    a = np.array
    cases = [
        ("lock_strain", lock_strain(h), 0.11055429),
        ("EOS elastic p", pressure(h, a(5e-4), a(0.0), a(0.0))[0], 8.0e6),
        ("EOS crushing p", pressure(h, a(0.05), a(0.03), a(0.0))[0], 366.65720e6),
        ("EOS crushing d_mu_p", pressure(h, a(0.05), a(0.03), a(0.0))[2], 0.018699343),
        ("EOS crushing tangent", pressure(h, a(0.05), a(0.03), a(0.0))[3], 46.861412e9),
        ("EOS unloading p", pressure(h, a(0.045), a(0.05), a(0.0))[0], 132.35014e6),
        ("EOS dense p", pressure(h, a(0.12), a(0.0), a(0.0))[0], 1490.1758e6),
        ("EOS dense d_mu_p", pressure(h, a(0.12), a(0.0), a(0.0))[2], 0.10114252),
        ("EOS dense tangent", pressure(h, a(0.12), a(0.0), a(0.0))[3], 71.807363e9),
        ("EOS cut-off D=0.5", pressure(h, a(0.03), a(0.05), a(0.5))[0], -2.0e6),
        ("yield P*=2 D=0.2 100/s", yield_stress(h, a(96e6), a(0.2), a(100.0)), 152.30924e6),
        ("yield p=-2MPa", yield_stress(h, a(-2e6), a(0.2), a(100.0)), 15.656959e6),
        ("yield S_max cap", yield_stress(h, a(2.4e9), a(0.0), a(100.0)), 336.0e6),
        ("yield below rate ref", yield_stress(h, a(96e6), a(0.0), a(0.1)), 155.13671e6),
        ("damage p=96MPa", damage_increment(h, a(96e6), 0.01, 0.002), 0.144),
        ("damage p=-3MPa", damage_increment(h, a(-3e6), 0.01, 0.002), 1.2),
        ("sound speed K_el", sound_speed(h, 16e9), 3831.1350),
        ("from_fc(48) G", from_fc(48e6, 2440.0).shear_modulus, 13654.334e6),
        ("from_fc(48) mu_crush", from_fc(48e6, 2440.0).mu_crush, 8.7884185e-4),
        ("from_fc(48) T", from_fc(48e6, 2440.0).t, 4.2954860e6),
    ]
    worst = 0.0
    for name, got, want in cases:
        worst = max(worst, abs(rel(float(got), want)))
    print(f"0. transcription: {len(cases)} values from the hjc.rs unit tests, "
          f"largest relative difference {worst:.1e}  -> {'PASS' if worst < 2e-5 else 'FAIL'}")
    return worst < 2e-5


def check_elastic(geometry):
    """Linear elastic, u_a << a0: sigma_r(a) = 2 k G u_a / a0 (compression positive; k = 2
    spherical, 1 cylindrical)."""
    mat = ElasticPlastic(200e9, 0.3, 7850.0)
    a0, speed, a_end = 1.0e-3, 0.2, 1.002
    t0 = time.time()
    res = expand_cavity(mat, speed, a0=a0, a_end=a_end, merge_frac=0.0, geometry=geometry)
    ok = True
    print(f"1. elastic, {geometry.name} (E 200 GPa, nu 0.3, V {speed} m/s, a/a0 -> {a_end}; "
          f"{res['steps']} steps, {time.time() - t0:.1f} s)")
    for x in (1.001, 1.0015, 1.002):
        want = 2.0 * geometry.k * mat.shear * (x - 1.0)
        wall, zone = value_at(res, "wall", x), value_at(res, "zone", x)
        ok &= abs(rel(wall, want)) < 0.03
        print(f"   a/a0 {x:.4f}: {2 * geometry.k}G u/a0 = {want / 1e6:8.2f} MPa | wall traction "
              f"{wall / 1e6:8.2f} ({100 * rel(wall, want):+5.2f} %) | innermost zone "
              f"{zone / 1e6:8.2f} ({100 * rel(zone, want):+5.2f} %)")
    print(f"   -> {'PASS' if ok else 'FAIL'} (wall traction within 3 %)")
    return ok


def check_hill(youngs, nu, density, y, speed, merge_frac, geometry=SPHERICAL):
    """Elastic-perfectly plastic, expanded to a/a0 = 25: Hill's quasi-static limit pressure.
    Spherical: p = (2Y/3) [1 + ln(E / (3 (1 - nu) Y))], plastic zone (E/(3(1-nu)Y))^(1/3) a.
    Cylindrical (plane strain): Hill's incompressible p = k [1 + ln(G/k)], k = Y/sqrt(3) (von
    Mises in plane strain), plastic zone sqrt(G/k) a; checked with nu near 1/2."""
    mat = ElasticPlastic(youngs, nu, density, y)
    if geometry.k == 2:
        want = 2.0 * y / 3.0 * (1.0 + math.log(youngs / (3.0 * (1.0 - nu) * y)))
        zone_want, zone_rule = (youngs / (3 * (1 - nu) * y)) ** (1 / 3), "(E/(3(1-nu)Y))^(1/3)"
    else:
        k_shear = y / math.sqrt(3.0)
        want = k_shear * (1.0 + math.log(mat.shear / k_shear))
        zone_want, zone_rule = math.sqrt(mat.shear / k_shear), "sqrt(G/k)"
    t0 = time.time()
    res = expand_cavity(mat, speed, merge_frac=merge_frac, geometry=geometry)
    s = summarise(res)
    ok = abs(rel(s["wall"], want)) < 0.03
    print(f"2. Hill, {geometry.name} (E {youngs / 1e9:g} GPa, nu {nu}, Y {y / 1e6:g} MPa, "
          f"rho {density:g}, "
          f"V {speed:g} m/s, rho V^2 = {density * speed ** 2 / 1e6:.2f} MPa; {res['steps']} "
          f"steps, {res['merges']} merges, {time.time() - t0:.1f} s)")
    print(f"   Hill p_lim = {want / 1e6:.2f} MPa | wall traction <a/a0 15-25> "
          f"{s['wall'] / 1e6:.2f} MPa ({100 * rel(s['wall'], want):+.2f} %), change 15->25 "
          f"{s['wall_change'] / 1e6:+.2f} MPa | innermost zone {s['zone'] / 1e6:.2f} MPa "
          f"({100 * rel(s['zone'], want):+.2f} %)")
    print(f"   plastic zone to r/a = {s['plastic']:.2f} (Hill, incompressible: "
          f"{zone_rule} = {zone_want:.2f})"
          f"  -> {'PASS' if ok else 'FAIL'} (within 3 %)")
    return ok


# ---------------------------------------------------------------------------------------------
# Penetration depth of a rigid ogive from the cavity-expansion resistance (Forrestal's method)
# ---------------------------------------------------------------------------------------------

def ogive_resistance(sigma_n, speed, crh, samples=400):
    """Axial force over pi a^2 on a rigid, frictionless tangent ogive of CRH `crh` moving at
    `speed`, each surface point loaded by the normal stress sigma_n(V_n) of a cavity expanding
    at the normal speed V_n = V cos(phi) (phi: the angle of the ogive arc, pi/2 at the shank).
    With s = 2 crh a the ogive radius, r/a = 2 crh sin(phi) - (2 crh - 1), and
    F / (pi a^2) = 2 int sigma_n(V cos phi) cos phi (r/a)(s/a) dphi, which is 1 for sigma_n = 1
    and Forrestal's N = (8 crh - 1)/(24 crh^2) for sigma_n = V_n^2 / V^2."""
    phi0 = math.asin((2.0 * crh - 1.0) / (2.0 * crh))
    phi = np.linspace(phi0, 0.5 * math.pi, samples)
    r = 2.0 * crh * np.sin(phi) - (2.0 * crh - 1.0)
    f = sigma_n(speed * np.cos(phi)) * np.cos(phi) * r * (2.0 * crh)
    return 2.0 * float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(phi)))


def rigid_depth(resistance, mass, radius, speed, samples=2000):
    """Depth of a rigid projectile meeting the axial stress resistance(V) in the tunnel, with
    Forrestal's crater: a force growing linearly over the first 4a to its tunnel value at V1,
    so m (Vs^2 - V1^2) = 4a pi a^2 R(V1); then P = 4a + int_0^V1 m V dV / (pi a^2 R(V))."""
    area = math.pi * radius ** 2
    lo, hi = 0.0, speed
    if mass * speed ** 2 <= 4.0 * radius * area * resistance(0.0):
        return None   # stops in the crater: outside the equation's range
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if mass * (speed ** 2 - mid ** 2) > 4.0 * radius * area * resistance(mid):
            lo = mid
        else:
            hi = mid
    v1 = 0.5 * (lo + hi)
    v = np.linspace(0.0, v1, samples)
    g = mass * v / (area * np.array([resistance(x) for x in v]))
    return 4.0 * radius + float(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(v)))


def forrestal_equation(mass, radius, crh, density, fc, speed):
    """Forrestal et al. (1994), physics.md section 8 (S = 82.6 f_c^-0.544, f_c in MPa)."""
    n = (8.0 * crh - 1.0) / (24.0 * crh ** 2)
    s = 82.6 * (fc / 1.0e6) ** -0.544
    v1_sq = (mass * speed ** 2 - 4.0 * math.pi * radius ** 3 * s * fc) / (
        mass + 4.0 * math.pi * radius ** 3 * density * n)
    return (mass / (2.0 * math.pi * radius ** 2 * density * n)) * math.log(
        1.0 + n * density * v1_sq / (s * fc)) + 4.0 * radius


def read_shots(path):
    """velocity_m_s,mass_kg,fc_MPa,depth_m[,...] rows of a data file such as
    data/forrestal1994.csv ('#' lines are comments)."""
    shots = []
    with open(path) as f:
        raw = [ln.strip() for ln in f if ln.strip()]
    lines = [ln for ln in raw if not ln.startswith("#")]
    head = lines[0].split(",")
    if "velocity_m_s" not in head:
        # The header may itself be the last comment line (as in forrestal1994.csv).
        named = [ln.lstrip("#").strip() for ln in raw if ln.startswith("#") and "," in ln]
        head = named[-1].split(",") if named else head
    else:
        lines = lines[1:]
    need = ("velocity_m_s", "mass_kg", "fc_MPa", "depth_m")
    missing = [k for k in need if k not in head]
    if missing:
        raise SystemExit(f"{path}: missing column(s) {missing} in header {head}")
    for ln in lines:
        cells = dict(zip(head, ln.split(",")))
        shots.append({k: float(cells[k]) for k in need})
    return shots


def run_shots(path, density, radius, crh, speeds, use_rate, merge_frac, a_end, overrides,
              geometry=SPHERICAL):
    """For each measured shot: the depth a rigid ogive reaches against the cavity-expansion
    resistance of the f_c rule's HJC concrete (at the shot's f_c), beside the measured depth
    and Forrestal's equation. Also checks the integration: Forrestal's own sigma_n = S f_c +
    rho V_n^2 put through ogive_resistance and rigid_depth must give the closed form."""
    shots = read_shots(path)
    print(f"{'V m/s':>6} {'f_c MPa':>7} {'measured':>9} {'equation':>9} {'err':>7} "
          f"{'HJC cavity':>10} {'err':>7} {'R(0) MPa':>8} {'R(100)':>7} {'R(220)':>7} "
          f"{'R(400)':>7} {'check':>9}")
    errs_eq, errs_cav = [], []
    tables = {}
    for shot in shots:
        fc = shot["fc_MPa"] * 1.0e6
        if fc not in tables:
            _, rows = run_hjc(fc, density, speeds, use_rate, merge_frac, a_end, overrides,
                              geometry)
            tables[fc] = (np.array([0.0] + [s["v"] for s in rows]),
                          np.array([rows[0]["wall"]] + [s["wall"] for s in rows]))
        vs, walls = tables[fc]

        def sigma_n(vn, vs=vs, walls=walls):
            if np.max(vn) > vs[-1] * (1.0 + 1e-9):
                raise SystemExit(f"normal speed {np.max(vn):.1f} m/s beyond the table "
                                 f"({vs[-1]:g} m/s): add a faster --speeds entry")
            return np.interp(vn, vs, walls)

        def resistance(v, sigma_n=sigma_n):
            return ogive_resistance(sigma_n, v, crh)

        depth = rigid_depth(resistance, shot["mass_kg"], radius, shot["velocity_m_s"])
        if depth is None:
            print(f"{shot['velocity_m_s']:6.0f}: stops within Forrestal's crater (4a), where "
                  "this integration does not apply; left out")
            continue
        eq = forrestal_equation(shot["mass_kg"], radius, crh, density, fc, shot["velocity_m_s"])
        s_emp = 82.6 * (fc / 1.0e6) ** -0.544

        def law(v, s_emp=s_emp, fc=fc):
            return ogive_resistance(lambda vn: s_emp * fc + density * vn ** 2, v, crh)

        check = rigid_depth(law, shot["mass_kg"], radius, shot["velocity_m_s"])
        meas = shot["depth_m"]
        e_eq, e_cav = (eq - meas) / meas, (depth - meas) / meas
        errs_eq.append(abs(e_eq))
        errs_cav.append(abs(e_cav))
        print(f"{shot['velocity_m_s']:6.0f} {fc / 1e6:7.1f} {meas:9.3f} {eq:9.4f} "
              f"{100 * e_eq:+6.1f}% {depth:10.4f} {100 * e_cav:+6.1f}% "
              f"{resistance(0.0) / 1e6:8.1f} {resistance(100.0) / 1e6:7.1f} "
              f"{resistance(220.0) / 1e6:7.1f} {resistance(400.0) / 1e6:7.1f} "
              f"{100 * (check - eq) / eq:+8.3f}%")
    if errs_cav:
        print(f"mean absolute error over {len(errs_cav)} shot(s): Forrestal's equation "
              f"{100 * np.mean(errs_eq):.1f} %, HJC cavity expansion {100 * np.mean(errs_cav):.1f} %")
    print("R(V): the resistance F/(pi a^2) on the ogive at V m/s (MPa); check: Forrestal's "
          "sigma_n = S f_c + rho V_n^2 through the same ogive integration and crater rule, "
          "against the closed form (must be ~0)")


def check_ogive():
    """3. The ogive integration and the crater rule of --shots: a uniform normal stress gives the
    projected area, a stress V_n^2 gives Forrestal's N, and Forrestal's own sigma_n put through
    rigid_depth gives his closed-form depth (the 499 m/s shot)."""
    ok = True
    for crh in (1.0, 2.0, 3.0):
        uniform = ogive_resistance(lambda vn: np.ones_like(vn), 100.0, crh)
        n = ogive_resistance(lambda vn: (vn / 100.0) ** 2, 100.0, crh)
        want = (8.0 * crh - 1.0) / (24.0 * crh ** 2)
        good = abs(uniform - 1.0) < 1e-4 and abs(n / want - 1.0) < 1e-4
        ok &= good
        print(f"3. ogive CRH {crh:g}: uniform stress -> {uniform:.6f} (1), V_n^2 -> {n:.6f} "
              f"(N = {want:.6f}) -> {'PASS' if good else 'FAIL'}")
    fc, density, mass, radius, speed = 33.5e6, 2370.0, 0.912, 0.01345, 499.0
    s_emp = 82.6 * (fc / 1.0e6) ** -0.544
    depth = rigid_depth(lambda v: ogive_resistance(lambda vn: s_emp * fc + density * vn ** 2,
                                                    v, 2.0), mass, radius, speed)
    want = forrestal_equation(mass, radius, 2.0, density, fc, speed)
    good = abs(depth / want - 1.0) < 1e-4
    print(f"3. Forrestal's law through rigid_depth: {depth:.5f} m, closed form {want:.5f} m "
          f"-> {'PASS' if good else 'FAIL'}")
    return ok and good


# ---------------------------------------------------------------------------------------------
# Main
# ---------------------------------------------------------------------------------------------

def run_hjc(fc, density, speeds, use_rate, merge_frac, a_end, overrides=None,
            geometry=SPHERICAL):
    h = replace(from_fc(fc, density), **(overrides or {}))
    mat = HjcMaterial(h, use_rate)
    rows = []
    for v in speeds:
        t0 = time.time()
        res = expand_cavity(mat, v, a_end=a_end, merge_frac=merge_frac, geometry=geometry)
        s = summarise(res)
        s.update(v=v, seconds=time.time() - t0, steps=res["steps"], merges=res["merges"])
        rows.append(s)
        print(f"   done V {v:g} m/s, rate {'on' if use_rate else 'off'}: {res['steps']} steps, "
              f"{res['merges']} merges, {s['seconds']:.1f} s", flush=True)
    return h, rows


def print_table(fc, density, h, rows_by_rate, geometry=SPHERICAL):
    print()
    print(f"HJC {geometry.name} cavity expansion, f_c = {fc / 1e6:g} MPa, "
          f"rho0 = {density:g} kg/m^3 "
          f"(G = {h.shear_modulus / 1e9:.2f} GPa, K_el = {h.p_crush / h.mu_crush / 1e9:.2f} GPa,"
          f" T = {h.t / 1e6:.2f} MPa, mu_plock = {lock_strain(h):.4f})")
    print("sigma_r: mean over a/a0 in [15, 25], compression positive; 'change' = mean[24,25] -"
          " mean[15,16]; wall = traction on the wall node, zone = innermost zone (incl. q)")
    head = (f"{'rate':>4} {'V m/s':>6} {'wall MPa':>9} {'wall/fc':>8} {'change':>8} "
            f"{'zone MPa':>9} {'zone/fc':>8} {'change':>8} {'rhoV2/fc':>8} {'plast r/a':>9} "
            f"{'D=1 r/a':>8} {'(outer)':>8} {'max mu':>7} {'front/R':>7} {'time s':>6}")
    print(head)
    print("-" * len(head))
    for label, rows in rows_by_rate:
        for s in rows:
            print(f"{label:>4} {s['v']:6.0f} {s['wall'] / 1e6:9.2f} {s['wall'] / fc:8.3f} "
                  f"{s['wall_change'] / 1e6:+8.2f} {s['zone'] / 1e6:9.2f} {s['zone'] / fc:8.3f} "
                  f"{s['zone_change'] / 1e6:+8.2f} {density * s['v'] ** 2 / fc:8.3f} "
                  f"{s['plastic']:9.2f} {s['d1_contig']:8.2f} {s['d1_outer']:8.2f} "
                  f"{s['mu_max']:7.4f} {s['front']:7.2f} {s['seconds']:6.1f}")
    print("D=1 r/a: outer edge of the fully damaged layer contiguous with the wall; (outer): "
          "outermost zone with D = 1; max mu: largest rho/rho0 - 1 at the end; front/R: leading "
          "wave (|u| > 1e-6 V) over the outer radius (< 1: the far boundary was never reached).")
    for label, rows in rows_by_rate:
        if len(rows) < 2:
            continue
        # Least squares sigma = S f_c + B rho0 V^2 over the speeds (Forrestal's form).
        x = np.array([density * s["v"] ** 2 for s in rows])
        y = np.array([s["wall"] for s in rows])
        coef = np.linalg.lstsq(np.column_stack((np.full_like(x, fc), x)), y, rcond=None)[0]
        fit = coef[0] * fc + coef[1] * x
        print(f"rate {label}: fit of the wall traction to S f_c + B rho0 V^2: S = {coef[0]:.2f},"
              f" B = {coef[1]:.2f} (largest misfit {np.max(np.abs(fit - y)) / 1e6:.2f} MPa)")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fc", type=float, default=34.7e6, help="f_c in Pa")
    ap.add_argument("--density", type=float, default=2370.0, help="rho0 in kg/m^3")
    ap.add_argument("--speeds", default="25,50,100,200", help="wall speeds, m/s, comma-separated")
    ap.add_argument("--no-rate", action="store_true", help="switch the HJC rate term off")
    ap.add_argument("--both-rates", action="store_true", help="rate term on, then off")
    ap.add_argument("--check", action="store_true", help="run the verification only")
    ap.add_argument("--merge-frac", type=float, default=0.01,
                    help="merge zones thinner than this fraction of their radius")
    ap.add_argument("--a-end", type=float, default=25.0, help="final a/a0")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="override one HJC constant of the f_c rule's set (SI), e.g. "
                         "--set mu_lock=0.13; repeatable")
    ap.add_argument("--shots", metavar="CSV",
                    help="depths of a rigid CRH ogive against the cavity-expansion resistance, "
                         "for each shot of a data file such as data/forrestal1994.csv")
    ap.add_argument("--radius", type=float, default=0.01345, help="projectile radius a (m)")
    ap.add_argument("--crh", type=float, default=2.0, help="ogive calibre radius head")
    ap.add_argument("--geometry", choices=sorted(GEOMETRIES), default="spherical",
                    help="the cavity: spherical (Forrestal's theory) or cylindrical (plane "
                         "strain, the limit of an infinitely slender nose)")
    args = ap.parse_args(argv)
    geometry = GEOMETRIES[args.geometry]
    overrides = {}
    names = set(Hjc.__dataclass_fields__) - {"density", "fc"}  # --density, --fc, the shots
    for item in args.set:
        key, sep, value = item.partition("=")
        if not sep or key not in names:
            ap.error(f"--set {item!r}: expected KEY=VALUE with KEY one of {sorted(names)}")
        try:
            overrides[key] = float(value)
        except ValueError:
            ap.error(f"--set {item!r}: {value!r} is not a number")

    if args.check:
        t0 = time.time()
        ok = check_transcription()
        ok &= check_elastic(geometry)
        if geometry.k == 2:
            ok &= check_hill(27.9e9, 0.2, 2370.0, 30e6, 10.0, args.merge_frac)  # concrete-like
            ok &= check_hill(200e9, 0.3, 7850.0, 500e6, 20.0, args.merge_frac)   # steel-like
        else:   # Hill's cylindrical limit is the incompressible one: nu near 1/2
            ok &= check_hill(27.9e9, 0.495, 2370.0, 30e6, 10.0, args.merge_frac, geometry)
        ok &= check_ogive()
        print(f"verification {'PASSED' if ok else 'FAILED'} ({time.time() - t0:.1f} s)")
        return 0 if ok else 1

    speeds = [float(v) for v in args.speeds.split(",") if v.strip()]
    if args.shots:
        run_shots(args.shots, args.density, args.radius, args.crh, speeds, not args.no_rate,
                  args.merge_frac, args.a_end, overrides, geometry)
        return 0
    rates = [True, False] if args.both_rates else [not args.no_rate]
    rows_by_rate = []
    h = None
    for use_rate in rates:
        h, rows = run_hjc(args.fc, args.density, speeds, use_rate, args.merge_frac, args.a_end,
                          overrides, geometry)
        rows_by_rate.append(("on" if use_rate else "off", rows))
    print_table(args.fc, args.density, h, rows_by_rate, geometry)
    return 0


if __name__ == "__main__":
    sys.exit(main())
