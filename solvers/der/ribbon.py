"""The twisted (or helical) LCE ribbon as a discrete elastic rod, heated by a hot ground.

Builds the rod from :mod:`lcefem.models.ribbon` (geometry, programmed shape, thermal natural
strains) and the LCE laws (shear modulus of ``LCEElasticity``, incompressible E = 3 mu), couples it
to the section heat model (:mod:`lcefem.solvers.der.heat`) by staggered steps (mechanics with the
natural shape of the current temperatures, then heat on the new geometry), and measures what the
experiments report: centroid path and speed, spin of both ends, contact points, twist density.

Also: :func:`ribbon_static_response`, the static shape of a free ribbon (no ground, optional
gravity) for given section temperatures, for comparisons with the 3D FE model.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from lcefem.models.contact import Block, ContactLaw, FrictionLaw, Wall
from lcefem.models.errors import InputError
from lcefem.models.heat import SurfaceExchange, ThermalProperties
from lcefem.models.hyperelastic import LCEElasticity
from lcefem.models.lce import MeasuredContraction, NematicTransition, contraction_ratio
from lcefem.models.parameters import param, with_overrides
from lcefem.models.ribbon import (
    SEED000_RIBBON,
    GroundHeatExchange,
    HelicoidCoupling,
    RibbonGeometry,
    SectionGrid,
    natural_strains,
)
from lcefem.models.rod import (
    RodSection,
    cross,
    material_curvatures,
    rectangular_section,
    signed_angle,
)
from lcefem.models.units import STANDARD_GRAVITY
from lcefem.solvers.der import frames as fr
from lcefem.solvers.der.assembly import (
    all_gaps,
    edge_corner_gaps,
    gap_slots,
    node_contact_forces,
    sample_points,
)
from lcefem.solvers.der.heat import HeatGeometry, SectionHeat
from lcefem.solvers.der.integrator import Integrator, StepControl, StepOptions
from lcefem.solvers.der.model import Box, DiscreteRod, Ground, RestShape, RodState, lumped_masses
from lcefem.solvers.der.newton import NewtonOptions
from lcefem.solvers.der.static import solve_static, statically_determinate_support
from lcefem.solvers.der.tabulated import TabulatedLaw


@dataclass(frozen=True)
class RibbonNumerics:
    """Discretisation and solver settings of the rolling-ribbon simulation."""

    nodes: int = param(60, "-", "chosen: rod nodes (edge ~1 mm at 60 mm length)", minimum=3)
    dt: float = param(
        0.01,
        "s",
        "chosen: time step (implicit Euler; with adaptive steps the first one and the "
        "record grid); the thermal time t^2/alpha ~ 5 s and the rolling period ~ 10 s are far "
        "longer",
        positive=True,
    )
    method: str = param("euler", "-", "'euler' (implicit Euler) or 'midpoint' (implicit midpoint)")
    error_tolerance: float = param(
        0.0,
        "mm",
        "chosen: local position error allowed per step of the adaptive step "
        "control (integrator.StepControl; implicit Euler only); 0: fixed steps of dt (default: "
        "above 100 C the "
        "runs depend on the step, and 1e-2 mm, 1.25 % of the thickness, agrees with fixed "
        "0.01 and 0.005 s steps at 100 C within 0.6 % but not at 120 C; README, Discrete "
        "Elastic Rods: adaptive steps)",
        minimum=0.0,
    )
    dt_min: float = param(
        1e-4,
        "s",
        "chosen: smallest adaptive step (below it a step is accepted whatever its "
        "error estimate; Newton failures still halve down to dt/256)",
        positive=True,
    )
    dt_max: float = param(
        0.05,
        "s",
        "chosen: largest adaptive step; also the heat step's, whose implicit Euler "
        "error is ~dt/(2 t_th) with the thermal time t_th = t^2/alpha ~ 5 s, i.e. 0.5 %",
        positive=True,
    )
    damping: float = param(
        0.02,
        "1/s",
        "assumed: mass-proportional viscous damping rate (still air); "
        "small, since rolling about the axis is resisted by nothing else",
        minimum=0.0,
    )
    settle_time: float = param(
        0.3, "s", "chosen: the ribbon settles on the cold ground before heating", minimum=0.0
    )
    force_tol: float = param(
        1e-5, "-", "Newton tolerance on forces, relative to a node's weight", positive=True
    )
    perturbation: float = param(
        0.01,
        "rad/s",
        "chosen imperfection: initial spin about the axis after "
        "settling, 1 % of the rolling rate, positive = the sense of the twist's "
        "handedness. A perfect ribbon with a whole number of half turns is symmetric "
        "under a half turn about the vertical, which swaps the rolling directions. "
        "Measured (issue 17, quick level, 100 C): 0.003, 0.01, 0.03 and -0.01 rad/s, "
        "and plate gradients of +-0.01-0.1 K/mm, all roll the same way at 0.54-0.56 "
        "mm/s: the model's direction is set by its own discrete asymmetry, not by "
        "these imperfections or round-off",
    )
    plate_gradient: float = param(
        0.0,
        "K/mm",
        "chosen imperfection: plate temperature gradient along +y "
        "(across the ribbon), T = T_ground + gradient (y - y_start); a persistent, "
        "physical symmetry breaking (a hot plate is uniform to ~1 K over its surface, "
        "i.e. gradients up to ~0.01-0.1 K/mm)",
    )
    contact_samples: int = param(
        2,
        "-",
        "chosen: sections sampled per edge for contact (frame angle interpolated with the twist)",
        minimum=1,
    )
    contact_spacing: float = param(
        0.0,
        "mm",
        "chosen: > 0 sets the contact sections per edge from a length instead of "
        "contact_samples: the smallest even count whose spacing along the as-built edge is at most "
        "this (at least 2). 0: contact_samples per edge whatever the edge length (the default). "
        "Measured (issue 32, 140 C, 180 s; validation/data/ribbon_node_study.csv): at a sample "
        "spacing of 0.19-0.3 mm 31 / 61 / 101 / 161 nodes roll at 6.92 / 7.70 / 8.06 / 8.23 mm/s, "
        "against 4.24 / 7.15 / 8.06 / 8.23 with 2 sections per edge. Keep the lock rate "
        "2 pi twist_density s / dt (the spin at which the plate contact passes one section of "
        "as-built spacing s per step) well above the rolling spin: with s = 0.25 mm and dt = "
        "0.01 s (7.85 rad/s, ~16 mm/s) the 140 and 180 C ribbons lock to it (15.99 mm/s, spin "
        "5 pi/2 rad/s) where dt = 0.005 s rolls at 9.88 mm/s (issue 32, docs/ribbon.md)",
        minimum=0.0,
    )
    cells_width: int = param(6, "-", "chosen: heat cells across the width", minimum=1)
    cells_thickness: int = param(
        2,
        "-",
        "chosen: heat cells through the 0.8 mm thickness. Not converged: speed over "
        "60-120 s on the plate (61 nodes, 0.01 s; issue 32, "
        "validation/data/ribbon_heat_study.csv): "
        "2 / 4 / 8 cells roll at 6.62 / 8.61 / 9.17 mm/s at 100 C (4 -> 8: +6.5 %) and 4.10 / 2.44 "
        "/ 2.97 mm/s at 180 C; none rolls at 55 C. 4 is the converged choice at 100 C, but with it "
        "the quick level (24 nodes, 0.02 s, 60 s) does not roll at 100 C (ribbon_threshold, "
        "ribbon_end_spin), so the change waits for the threshold sweep at both levels "
        "(docs/ribbon.md)",
        minimum=1,
    )
    lag_tol: float = param(
        0.1,
        "-",
        "chosen: below this residual (relative to a node's weight, like force_tol) "
        "Newton reuses the last Hessian factor while the residual falls at least 4x per "
        "iteration (newton.minimise): the same equilibria to force_tol, fewer Hessian "
        "evaluations; 0: a fresh Hessian every iteration",
        minimum=0.0,
    )
    watchdog: int = param(
        0,
        "-",
        "chosen: full Newton steps allowed to raise the incremental potential before the "
        "line search backtracks (NewtonOptions.watchdog; 3 elsewhere). In a contact event the full "
        "step slides the ribbon along a soft (inertia-only) direction, 0.2-0.7 mm against a "
        "~0.01 mm correction, and the watched steps cycled back to the checkpoint for up to 30 "
        "iterations. Measured (issue 17, rolling, 70-73 s on the 100 C plate, same state): 5.15 -> "
        "4.00 Newton/step and 4.6 -> 3.5 Hessians/step at 100 nodes, 13.0 -> 6.0 Newton/step at "
        "31 nodes; the 16-node landing 312 -> 89 iterations (README, fifth pass)",
        minimum=0,
    )
    elastic_hessian_at_source: bool = param(
        False,
        "-",
        "chosen: True: the Newton iterates of a step take the elastic Hessian of their transport "
        "source "
        "(StepOptions.elastic_hessian_at_source; inertia, contact and friction Hessians their "
        "own). Measured (issue "
        "17, rolling, same state): 17-19 % less mechanics CPU at 60 and 100 nodes, 4 % at 31; but "
        "the default-level "
        "100 C speed (31 nodes, 60 s) 2.495 +- 0.005 mm/s against 2.520 +- 0.014 with exact "
        "Hessians (imperfection "
        "0.0099 / 0.01 / 0.0101 rad/s); the paths agree to 1e-8 mm until the rolling onset (35 "
        "s), which parts "
        "them, so the shift may be the onset's sensitivity; off until settled (README, fifth pass)",
    )
    heat_dt: float = param(
        0.0,
        "s",
        "chosen: multirate heat step. The section heat step is taken once this much "
        "mechanics time has passed, over that whole time, on the geometry at its end, and the "
        "mechanics steps in between take the natural shape of the last two heat steps taken "
        "linearly in time to t - (heat_dt + dt)/2, which keeps the single-rate "
        "heat-to-mechanics delay of dt/2 (a natural shape that jumps every few steps shakes "
        "the contacts: 3x the Newton iterations while rolling; lagging by heat_dt slowed the "
        "100 C rolling by 1.4 / 6.4 % at 0.02 / 0.05 s). 0: a heat step after every mechanics "
        "step. "
        "Why it may be longer: the thermal time t^2/alpha ~ 5 s is 500x the mechanics step. "
        "Measured (issue 17, 31 nodes, 60 s): 0.02 s moves the 100 C speed by -0.25 % (0.05 s: "
        "-2.1 %), but with 0.005 s steps at 140 C it stops the rolling, hence the default 0 "
        "(README, Rolling-step cost, fourth pass)",
        minimum=0.0,
    )
    section_quadrature: int = param(
        4,
        "-",
        "chosen: Gauss points per cell and direction of the eigenstrain "
        "resultants; one-face bending within 1e-5 of the beam closed form on the "
        "6 x 2 grid (rod_closed_forms case; 1 point: -27 %)",
        minimum=1,
    )


def contact_samples_per_edge(numerics: RibbonNumerics, length: float) -> int:
    """Contact sections per edge: ``numerics.contact_samples``, or with ``contact_spacing`` > 0 the
    smallest even count (at least 2) whose spacing along an as-built edge of a rod of ``length``
    [mm] is at most it."""
    if numerics.contact_spacing <= 0:
        return numerics.contact_samples
    edge = length / (numerics.nodes - 1)
    return max(2, 2 * math.ceil(edge / numerics.contact_spacing / 2.0 - 1e-9))


def lce_ribbon_section(
    geometry: RibbonGeometry,
    elasticity: LCEElasticity = LCEElasticity(),
    thermal: ThermalProperties = ThermalProperties(),
) -> RodSection:
    """Rectangular section with E = 3 mu (incompressible small-strain limit of ``LCEElasticity``)
    and G = mu; width along m1, thickness along m2."""
    mu = elasticity.shear_modulus
    return rectangular_section(geometry.width, geometry.thickness, 3.0 * mu, mu, thermal.density)


def programmed_shape(
    geometry: RibbonGeometry, state: RodState, elasticity: LCEElasticity = LCEElasticity()
) -> "ProgrammedShape":
    """As-built natural shape of ``state``: a twisted ribbon (director along its twisted fibres)
    with the helicoid's twist-stretch coupling (E = 3 mu, G = mu), or a helical ribbon (director
    along the centreline, no coupling)."""
    if geometry.is_helical:
        return ProgrammedShape.of_state(state, twisted_director=False)
    mu = elasticity.shear_modulus
    return ProgrammedShape.of_state(
        state, True, HelicoidCoupling.of(geometry, 3.0 * mu, mu).locked(geometry.twist_lock)
    )


def corner_radius(geometry: RibbonGeometry) -> float:
    """Distance from the centreline to a corner of the section, sqrt(w^2 + t^2)/2 [mm]."""
    return 0.5 * math.hypot(geometry.width, geometry.thickness)


def initial_ribbon_state(
    geometry: RibbonGeometry, n_nodes: int, phase: float = 0.0, lift: float = 0.0
) -> RodState:
    """As-built ribbon lying along x on the plane z = 0 (its lowest corner at height ``lift``).

    Twisted ribbon: straight centreline, m1 (width) turned by tau_0 s + phase about x.
    Helical ribbon: centreline (c phi, R cos phi, R sin phi), c = pitch/(2 pi), phi = s/sqrt(R^2 +
    c^2), a helix of radius R about the x axis with the face normal m2 pointing to the helix axis
    (the ribbon wound on a cylinder, face on it), resting on its lowest corner.
    """
    if n_nodes < 3:
        raise InputError(f"nodes = {n_nodes}: must be >= 3")
    L = geometry.length
    s = np.linspace(0.0, L, n_nodes)
    if not geometry.is_helical:
        x = np.zeros((n_nodes, 3))
        x[:, 0] = s
        x[:, 2] = corner_radius(geometry) + lift
        mid = 0.5 * (s[:-1] + s[1:])
        theta = geometry.twist_rate * mid + phase
        state = RodState.from_positions(x, theta, first_director=np.array([0.0, 0.0, 1.0]))
        return _lay_on_ground(state, geometry, lift)
    R = geometry.helix_radius
    c = geometry.helix_pitch / (2.0 * math.pi)
    phi = s / math.hypot(R, c) + phase
    x = np.stack([c * phi, R * np.cos(phi), R * np.sin(phi)], axis=1)
    state = RodState.from_positions(x, first_director=np.array([0.0, 0.0, 1.0]))
    # Turn each material frame so that m2 points to the helix axis (curvature towards m2).
    mid = 0.5 * (x[:-1] + x[1:])
    inward = -mid.copy()
    inward[:, 0] = 0.0
    t = state.tangents
    inward -= np.einsum("ki,ki->k", inward, t)[:, None] * t
    inward = fr.unit(inward)
    m1_target = cross(inward, t)
    theta = signed_angle(state.a1, m1_target, t)
    theta = np.unwrap(theta)
    state = RodState.from_positions(x, theta, first_director=np.array([0.0, 0.0, 1.0]))
    return _lay_on_ground(state, geometry, lift)


def _lay_on_ground(state: RodState, geometry: RibbonGeometry, lift: float) -> RodState:
    """Shift the rod vertically so that its lowest section corner is at height ``lift``."""
    m1, m2 = state.material_frames()
    hw, ht = 0.5 * geometry.width, 0.5 * geometry.thickness
    cz = 0.5 * (state.x[:-1, 2] + state.x[1:, 2])
    lowest = cz - hw * np.abs(m1[:, 2]) - ht * np.abs(m2[:, 2])
    x = state.x.copy()
    x[:, 2] += lift - lowest.min()
    return RodState(x, state.theta, state.v, state.omega, state.a1, state.ref_twist, state.time)


@dataclass
class ProgrammedShape:
    """Stress-free shape of the as-built ribbon (integrated per node) and reference lengths."""

    edge_length: np.ndarray  # as-built rest edge lengths [mm]
    curvature: np.ndarray  # (N-2, 2) integrated [-]
    twist: np.ndarray  # (N-2,) integrated [rad]
    twisted_director: bool  # True: the twist was programmed by twisting a stretched strip
    coupling: HelicoidCoupling = field(default_factory=HelicoidCoupling)  # twisted director only

    @property
    def voronoi(self) -> np.ndarray:
        return 0.5 * (self.edge_length[:-1] + self.edge_length[1:])

    @classmethod
    def of_state(
        cls,
        state: RodState,
        twisted_director: bool,
        coupling: HelicoidCoupling = HelicoidCoupling(),
    ) -> "ProgrammedShape":
        """The as-built state is stress free: its measured curvatures and twist are the natural
        ones."""
        e = fr.edges_of(state.x)
        m1, m2 = state.material_frames()
        kappa = material_curvatures(e[:-1], e[1:], m1[:-1], m2[:-1], m1[1:], m2[1:])
        twist = state.theta[1:] - state.theta[:-1] + state.ref_twist
        return cls(np.linalg.norm(e, axis=1), kappa, twist, twisted_director, coupling)

    def rest_shape(
        self,
        cell_temperatures: np.ndarray,
        grid: SectionGrid,
        transition: NematicTransition,
        contraction=None,
    ) -> RestShape:
        """Natural shape at the given section cell temperatures (N-1, n_cells) [C] (module docstring
        of :mod:`lcefem.models.ribbon`; ``contraction`` as in ``natural_strains``)."""
        ns = natural_strains(cell_temperatures, grid, transition, contraction)
        node = lambda v: 0.5 * (v[:-1] + v[1:])  # noqa: E731  edges -> interior nodes
        vor = self.voronoi
        curvature = self.curvature + node(ns.curvature) * vor[:, None]
        stretch = 1.0 + ns.axial
        if self.twisted_director:
            twist = self.coupling.twist_factor(node(ns.contraction)) * self.twist
            stretch = stretch * self.coupling.stretch_factor(ns.contraction)
        else:
            twist = self.twist.copy()
        return RestShape(self.edge_length * stretch, curvature, twist)


HISTORY_COLUMNS = [
    "time [s]",
    "centroid_x [mm]",
    "centroid_y [mm]",
    "centroid_z [mm]",
    "speed [mm/s]",
    "spin_start [rad]",
    "spin_end [rad]",
    "twist_density [turns/mm]",
    "length [mm]",
    "contact_points [-]",
    "T_mean [C]",
    "T_max [C]",
    "newton_iterations [-]",
    "step_cuts [-]",
]


#: The rolling ribbon's as-built shape (issue 32): the assumed 60 x 4 x 0.8 mm, 0.05 turns/mm ribbon
#: with its programmed twist locked (``RibbonGeometry.twist_lock`` = 1: seed 000's ribbons keep
#: their twist density while rolling). The static FE comparisons keep the director-only coupling
#: (twist_lock 0).
ROLLING_RIBBON = RibbonGeometry(twist_lock=1.0)


@dataclass(frozen=True)
class RibbonSections:
    """The rolling ribbon's physical sections, defined once: the as-built shape, the numerics, the
    heat capacity and conduction, the exchange with air and with the plate, contact and friction.
    The run's configuration (lcefem.solvers.problems.twisted_ribbon_der.RibbonConfig, the case
    file's sections of the same names) and the simulation's setup (:class:`RibbonSetup`) both
    inherit them."""

    geometry: RibbonGeometry = ROLLING_RIBBON
    numerics: RibbonNumerics = field(default_factory=RibbonNumerics)
    thermal: ThermalProperties = field(default_factory=ThermalProperties)
    air: SurfaceExchange = field(default_factory=SurfaceExchange)
    ground_heat: GroundHeatExchange = field(default_factory=GroundHeatExchange)
    contact: ContactLaw = field(default_factory=ContactLaw)
    friction: FrictionLaw = field(default_factory=FrictionLaw)


@dataclass(frozen=True)
class RibbonSetup(RibbonSections):
    """What :class:`RibbonSimulation` is built from: the sections (:class:`RibbonSections`) plus the
    plate temperature, the material laws and the obstacles on the plate. The material defaults to
    seed 000's ribbon LCE (``models.ribbon.SEED000_RIBBON``, issue 32)."""

    ground_temperature: float = 80.0
    transition: NematicTransition | MeasuredContraction = field(
        default_factory=SEED000_RIBBON.transition
    )
    elasticity: LCEElasticity = field(default_factory=SEED000_RIBBON.elasticity)
    walls: tuple[Wall, ...] = ()  # obstacles on the plate, placed relative to the as-built ribbon
    blocks: tuple[
        Block, ...
    ] = ()  # blocks of finite size on the plate (those of width 0 are left out)


class RibbonSimulation:
    """A ribbon on a hot plate: build once, then :meth:`advance` in time."""

    def __init__(self, setup: RibbonSetup, on_failure=None):
        self.setup = s = setup
        g, num = s.geometry, s.numerics
        if num.method not in ("euler", "midpoint"):
            raise InputError(f"numerics.method = {num.method!r}: allowed euler, midpoint")
        self.section = section = lce_ribbon_section(g, s.elasticity, s.thermal)
        state = initial_ribbon_state(g, num.nodes)
        self.programmed = programmed_shape(g, state, s.elasticity)
        n = num.nodes
        node_mass, edge_inertia = lumped_masses(section, self.programmed.edge_length)
        self.grid = SectionGrid(
            g.width, g.thickness, num.cells_width, num.cells_thickness, num.section_quadrature
        )
        self.T = np.full((n - 1, self.grid.n_cells), s.air.ambient_temperature)
        self.contraction = tabulated_contraction(s.transition)
        rest = self.programmed.rest_shape(self.T, self.grid, s.transition, self.contraction)
        # natural shapes of the last two heat steps' temperatures, and the mechanics time since the
        # last one
        self._rest_from = self._rest_to = rest
        self._heat_elapsed = 0.0
        gravity = np.array([0.0, 0.0, -STANDARD_GRAVITY])
        walls = tuple(Ground(*w.plane(state.x)) for w in s.walls)
        boxes = tuple(
            Box(*b.box(state.x), b.edge_radius, b.friction) for b in s.blocks if b.present
        )
        self.rod = DiscreteRod(
            section,
            rest,
            node_mass,
            edge_inertia,
            gravity=gravity,
            damping=num.damping,
            ground=Ground(),
            contact=s.contact,
            friction=s.friction,
            obstacles=walls,
            boxes=boxes,
            contact_samples=contact_samples_per_edge(num, g.length),
        )
        self.options = self._step_options(num)
        self.integrator = Integrator(self.rod, state, self.options, on_failure=on_failure)
        self.control = None
        if num.error_tolerance > 0:
            if num.method != "euler":
                raise InputError(
                    f"numerics.method = {num.method!r}: adaptive steps (error_tolerance > 0) "
                    "need 'euler'"
                )
            self.control = StepControl(
                num.error_tolerance, num.dt_min, num.dt_max, corner_radius(g)
            )
        self.next_dt = num.dt  # the step the controller proposes next [s]
        self.rejected = 0  # adaptive steps rejected by the error estimate
        self.steps_taken = 0  # accepted steps on the hot plate
        self.heat = SectionHeat(
            n - 1,
            self.grid,
            self.programmed.edge_length,
            s.thermal,
            s.air,
            s.ground_heat,
            s.contact,
        )
        # blocks that exchange heat with the ribbon: (box, temperature [C]) (Block.heat; none by
        # default)
        self.heated_blocks = tuple(
            (box, b.block_temperature(s.ground_temperature, s.air.ambient_temperature))
            for b, box in zip([b for b in s.blocks if b.present], boxes)
            if b.block_temperature(s.ground_temperature, s.air.ambient_temperature) is not None
        )
        self._spin0 = None
        self._spin_prev = None
        self.time = 0.0
        self.last_report = None
        if num.settle_time > 0:
            self._settle(num.settle_time)
        self._perturb(num.perturbation)
        self._y_start = float(self.state.x[:, 1].mean())

    def __getstate__(self):
        """Pickled without the tabulated a(T) (rebuilt on loading): a pickle that an older package
        can load too (der_benchmark --same-state)."""
        state = dict(self.__dict__)
        state.pop("contraction", None)
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.contraction = tabulated_contraction(self.setup.transition)
        if "_heat_elapsed" not in state:  # pickled by a package without the multirate heat step
            self._heat_elapsed = 0.0
            self._rest_from = self._rest_to = self.programmed.rest_shape(
                self.T, self.grid, self.setup.transition, self.contraction
            )

    # -- stepping ----------------------------------------------------------------------------
    def _step_options(self, num: RibbonNumerics) -> StepOptions:
        """The integrator's options from the numerics: Newton's force tolerances relative to the
        heaviest node's weight [N], its step limits relative to the thickness [mm]."""
        g = self.setup.geometry
        weight = float(self.rod.node_mass.max() * STANDARD_GRAVITY)
        newton = NewtonOptions(
            max_iterations=80,
            force_tol=num.force_tol * weight,
            step_tol=1e-9 * g.thickness,
            max_rotation=0.2,
            max_displacement=0.25 * g.thickness,
            unchecked_step=1e-4 * g.thickness,
            lag_residual=num.lag_tol * weight,
            watchdog=num.watchdog,
        )
        # extrapolated guess: rolling is smooth, and it saves ~0.5 Newton iterations per step (issue
        # 17)
        return StepOptions(
            method=num.method,
            min_dt=num.dt / 256.0,
            extrapolate=True,
            newton=newton,
            elastic_hessian_at_source=num.elastic_hessian_at_source,
        )

    #: numerics a built simulation can change between steps (:meth:`change_solver`): the Newton
    #: loop's and the heat step's rate, not the discretisation
    SOLVER_FIELDS = ("force_tol", "lag_tol", "watchdog", "elastic_hessian_at_source", "heat_dt")

    def change_solver(self, **changes) -> None:
        """Take new solver numerics (``SOLVER_FIELDS`` of :class:`RibbonNumerics`) from the next
        step on, e.g. to time two solver settings from one state
        (``benchmarks/ribbon_benchmark.py``)."""
        for name in changes:
            if name not in self.SOLVER_FIELDS:
                raise InputError(
                    f"numerics.{name}: cannot change in a built simulation; allowed "
                    f"{', '.join(self.SOLVER_FIELDS)}"
                )
        num = with_overrides(self.setup.numerics, changes, "numerics")
        self.setup = replace(self.setup, numerics=num)
        self.options = self.integrator.options = self._step_options(num)

    @property
    def state(self) -> RodState:
        return self.integrator.state

    def _settle(self, duration: float) -> None:
        """Mechanics only, ground at ambient temperature (no heating), then time restarts at 0."""
        dt = self.setup.numerics.dt
        steps = max(1, int(round(duration / dt)))
        for _ in range(steps):
            self.integrator.step(dt)
        self.integrator.state.time = 0.0

    def _perturb(self, spin: float) -> None:
        """Roll the settled ribbon about its axis (x) at the rate ``spin`` [rad/s] times the
        handedness of its twist (+1 right-handed): every node gets the rigid velocity omega x (x -
        axis point on the plate). The documented imperfection that breaks the ribbon's half-turn
        symmetry (``RibbonNumerics.perturbation``)."""
        st = self.integrator.state
        spin = spin * (1.0 if self.setup.geometry.twist_density >= 0.0 else -1.0)
        w = np.array([spin, 0.0, 0.0])
        line = np.array(
            [0.0, st.x[:, 1].mean(), 0.0]
        )  # the contact line on the plate below the axis
        st.v = st.v + cross(w, st.x - line)
        if not self.setup.geometry.is_helical:
            st.omega = st.omega + spin * np.sign(st.tangents[:, 0])

    def heat_geometry(self) -> HeatGeometry:
        st = self.state
        geo = st.geometry()
        return HeatGeometry(
            0.5 * (st.x[:-1] + st.x[1:]), geo.m1, geo.m2, geo.length, self.corner_gaps()
        )

    def advance(self, t_end: float) -> None:
        """Step to the time t_end [s] exactly: fixed steps of at most ``numerics.dt``, or adaptive
        steps (``numerics.error_tolerance`` > 0) chosen by :class:`StepControl` (a rejected step is
        retried from the same state with the smaller step the controller proposes). A step that
        would leave a sliver before t_end is shortened to half the remainder instead."""
        while t_end - self.time > 1e-9 * max(1.0, abs(t_end)):
            remaining = t_end - self.time
            planned = self.next_dt if self.control is not None else self.setup.numerics.dt
            h = planned
            if h >= remaining * (1.0 - 1e-9):
                h = remaining
            elif h > 0.5 * remaining:
                h = 0.5 * remaining
            rejected = self.rejected
            self.step(h)
            if h < planned and self.rejected == rejected:
                # shortened only to land on t_end: the controller's step still holds
                self.next_dt = max(self.next_dt, planned)

    def step(self, dt: float):
        """One mechanics step of dt [s], then the heat step on the new geometry once
        ``numerics.heat_dt`` of mechanics time has passed since the last one (after every step with
        0); the mechanics take the natural shape of the last two heat steps, taken linearly to t -
        (heat_dt + dt)/2 (the latest with heat_dt = 0). With adaptive steps a step whose error
        estimate exceeds the tolerance is retried with a smaller step, so the step taken may be
        shorter than dt (``last_report.dt``)."""
        s = self.setup
        span = s.numerics.heat_dt
        # the natural shape at t - (span + dt)/2 from the last two heat steps (the heat step takes
        # the geometry at its interval's end, span/2 ahead of the interval's middle: together the
        # heat-to-mechanics delay stays dt/2, that of the single-rate staggered scheme; an
        # interpolation lagging by span instead slowed the 100 C rolling by 6 % at span 0.05 s,
        # issue 17)
        frac = 1.0 if span <= dt else min(2.0, 0.5 + (self._heat_elapsed + 0.5 * dt) / span)
        self.rod.rest = (
            self._rest_to if frac == 1.0 else _interpolated(self._rest_from, self._rest_to, frac)
        )
        while True:
            new, report = self.integrator.trial(dt)
            if self.control is None:
                break
            error = self.control.error(self.state, new)
            proposal = self.control.next_dt(dt, error)
            if error <= self.control.tolerance or dt <= self.control.dt_min:
                self.next_dt = proposal
                break
            self.rejected += 1
            dt = proposal
        self.integrator.state = new
        self.time = self.state.time
        self.steps_taken += 1
        self.last_report = report
        self._heat_elapsed += dt
        if self._heat_elapsed < span * (1.0 - 1e-9):
            return report
        dt, self._heat_elapsed = self._heat_elapsed, 0.0
        gradient = None
        if s.numerics.plate_gradient:
            # zero at the starting centreline: the mean plate temperature under the ribbon is
            # T_ground
            gradient = np.array([0.0, s.numerics.plate_gradient, 0.0])
        T_ground = s.ground_temperature - (s.numerics.plate_gradient * self._y_start)
        blocks = tuple(
            (box, T_b, self.block_corner_gaps(box))
            for box, T_b in self.__dict__.get("heated_blocks", ())
        )
        self.T, self.fluxes = self.heat.step(
            self.T, dt, self.heat_geometry(), T_ground, gradient, blocks=blocks
        )
        rest = self.programmed.rest_shape(self.T, self.grid, s.transition, self.contraction)
        self._rest_from, self._rest_to = self._rest_to, rest
        return report

    # -- observables -------------------------------------------------------------------------
    def end_spins(self) -> tuple[float, float]:
        """Rotation angles [rad] of the first and last edge's width direction about the x axis
        (unwrapped in time, zero at the first call)."""
        m1, _ = self.state.material_frames()
        ang = np.arctan2(m1[[0, -1], 2], m1[[0, -1], 1])
        if self._spin_prev is None:
            self._spin0 = ang.copy()
            self._spin_acc = np.zeros(2)
        else:
            self._spin_acc += np.angle(np.exp(1j * (ang - self._spin_prev)))
        self._spin_prev = ang
        return float(self._spin_acc[0]), float(self._spin_acc[1])

    def wall_gaps(self) -> np.ndarray:
        """Smallest gap [mm] of the ribbon's sample points to each wall, (n_walls,)."""
        out = []
        for wall in self.rod.obstacles:
            gs, ge = all_gaps(self.rod, self.state, self.integrator.sampling, wall)
            out.append(min(ge.min(), gs.min() if gs is not None else np.inf))
        return np.array(out)

    def block_gaps(self) -> np.ndarray:
        """Smallest gap [mm] of the ribbon's sample points to each block, (n_blocks,)."""
        out = []
        for box in self.rod.boxes:
            gs, ge = all_gaps(self.rod, self.state, self.integrator.sampling, box)
            out.append(min(ge.min(), gs.min()) if gs is not None else ge.min())
        return np.array(out)

    def block_corner_gaps(self, box: Box) -> np.ndarray:
        """Smallest gap [mm] of each corner over each edge's samples to the block ``box``, (N-1, 4)
        (as
        :meth:`corner_gaps` for the plate)."""
        sampling = self.integrator.sampling
        n_edges = self.rod.n_nodes - 1
        pos_s, _, pos_e, _ = sample_points(self.state, sampling)
        side, slot_s, slot_e = gap_slots(sampling)
        out = np.full((n_edges, len(sampling.offsets)), np.inf)
        ends = sampling.end_edges(n_edges)
        np.minimum.at(
            out,
            (np.repeat(ends, pos_e.shape[1]), np.tile(slot_e, len(ends))),
            box.gaps(pos_e).ravel(),
        )
        if sampling.interpolated:
            edges = np.arange(pos_s.shape[0])[:, None] + side[None, :]
            np.minimum.at(
                out,
                (edges.ravel(), np.broadcast_to(slot_s, edges.shape).ravel()),
                box.gaps(pos_s).ravel(),
            )
        return out

    def corner_gaps(self) -> np.ndarray:
        """Smallest gap [mm] of each corner over each edge's samples, (N-1, 4)."""
        return edge_corner_gaps(self.rod, self.state, self.integrator.sampling)

    def contact_count(self) -> int:
        """Number of contact regions: runs of consecutive edges with a corner within delta of the
        plate."""
        touching = (self.corner_gaps() < self.setup.contact.delta).any(axis=1).astype(int)
        return int(np.count_nonzero(np.diff(np.concatenate([[0], touching])) == 1))

    def contact_forces(self) -> np.ndarray:
        """Contact force vector per node (N, 3) [N]."""
        return node_contact_forces(self.rod, self.state, self.integrator.sampling)

    def twist_density(self) -> float:
        """Mean twist density of the interior [turns/mm]."""
        st = self.state
        tw = st.theta[1:] - st.theta[:-1] + st.ref_twist
        length = np.linalg.norm(fr.edges_of(st.x), axis=1)
        return float(tw.sum() / (length.sum() - 0.5 * (length[0] + length[-1])) / (2.0 * math.pi))

    def observe(self) -> dict:
        st = self.state
        c = st.x.mean(axis=0)
        v = st.v.mean(axis=0)
        s0, s1 = self.end_spins()
        rep = self.last_report
        length = float(np.linalg.norm(fr.edges_of(st.x), axis=1).sum())
        return {
            "time [s]": st.time,
            "centroid_x [mm]": c[0],
            "centroid_y [mm]": c[1],
            "centroid_z [mm]": c[2],
            "speed [mm/s]": float(np.hypot(v[0], v[1])),
            "spin_start [rad]": s0,
            "spin_end [rad]": s1,
            "twist_density [turns/mm]": self.twist_density(),
            "length [mm]": length,
            "contact_points [-]": self.contact_count(),
            "T_mean [C]": float(self.T.mean()),
            "T_max [C]": float(self.T.max()),
            "newton_iterations [-]": rep.iterations if rep else 0,
            "step_cuts [-]": rep.cuts if rep else 0,
        }

    def node_temperatures(self) -> np.ndarray:
        """Mean section temperature at the nodes (N,) [C] (edge values averaged, ends copied)."""
        te = self.T.mean(axis=1)
        out = np.empty(len(te) + 1)
        out[1:-1] = 0.5 * (te[:-1] + te[1:])
        out[0], out[-1] = te[0], te[-1]
        return out


#: Range and spacing of the tabulated contraction ratio a(T) [C]: the plates and the air span 20-140
#: C (outside it a(T) is evaluated exactly); max error ~1e-10 (``tabulated.TabulatedLaw.max_error``)
CONTRACTION_TABLE = (-50.0, 350.0, 0.05)


@functools.lru_cache(maxsize=8)
def tabulated_contraction(transition: NematicTransition | MeasuredContraction) -> TabulatedLaw:
    """a(T) = ``models.lce.contraction_ratio`` tabulated on ``CONTRACTION_TABLE`` (one table per
    transition; a measured curve's piecewise-linear a(T) too: at the table's nodes it is exact)."""
    return TabulatedLaw.of(
        functools.partial(contraction_ratio, transition=transition), *CONTRACTION_TABLE
    )


def _interpolated(a: RestShape, b: RestShape, frac: float) -> RestShape:
    """(1 - frac) a + frac b, field by field [mm, -, rad]."""
    return RestShape(
        a.edge_length + frac * (b.edge_length - a.edge_length),
        a.curvature + frac * (b.curvature - a.curvature),
        a.twist + frac * (b.twist - a.twist),
    )


# ----------------------------------------------------------------------------------------------
# Static response (for the FE comparisons)
# ----------------------------------------------------------------------------------------------
@dataclass
class StaticResponse:
    """Static shape of a free ribbon.

    Attributes:
        state: the equilibrium rod state.
        curvature: (N-2, 2) curvature densities (towards m1, towards m2) at interior nodes [1/mm].
        twist_density: (N-2,) twist densities at interior nodes [rad/mm].
        length: centreline length [mm].
        mean_curvature: (2,) interior means [1/mm]; mean_twist_density [rad/mm].
    """

    state: RodState
    curvature: np.ndarray
    twist_density: np.ndarray
    length: float
    mean_curvature: np.ndarray
    mean_twist_density: float


def ribbon_static_response(
    geometry: RibbonGeometry,
    n_nodes: int,
    *,
    face_temperatures=None,
    cell_temperatures=None,
    grid: SectionGrid | None = None,
    transition: NematicTransition = NematicTransition(),
    elasticity: LCEElasticity = LCEElasticity(),
    thermal: ThermalProperties = ThermalProperties(),
    gravity: bool = False,
    increments: int = 4,
) -> StaticResponse:
    """Static equilibrium of the free ribbon (no ground) at given section temperatures.

    Args:
        geometry: as-built ribbon (twist density 0 for a straight strip).
        n_nodes: rod nodes (>= 3).
        face_temperatures: (T_plus, T_minus) [C], scalars, per node (N,) or per edge (N-1,): a
            linear profile through the thickness, T_plus on the face towards m2, T_minus on the face
            towards -m2 (node values are averaged onto the edges).
            At s = 0 m1 (width) is +z and m2 = t x m1 = -y; along the ribbon both turn by tau_0 s
            about x.
        cell_temperatures: alternatively (n_cells,) or (N-1, n_cells) [C] on ``grid``.
        grid: section cells (default 6 x 2).
        gravity: include the ribbon's weight (along -z); the rod is held by a statically determinate
            support at its first edge either way (no rigid motion, no reaction without gravity).

    Returns:
        :class:`StaticResponse` (curvatures and twist by the discrete formulas divided by the
        current Voronoi lengths; means over the interior nodes away from the ends).
    """
    if n_nodes < 3:
        raise InputError(f"nodes = {n_nodes}: must be >= 3")
    grid = grid or SectionGrid(geometry.width, geometry.thickness)
    if (face_temperatures is None) == (cell_temperatures is None):
        raise InputError("give exactly one of face_temperatures, cell_temperatures")
    if face_temperatures is not None:
        faces = []
        for T_face in face_temperatures:
            T_face = np.asarray(T_face, float)
            if T_face.ndim == 1 and len(T_face) == n_nodes:
                T_face = 0.5 * (T_face[:-1] + T_face[1:])
            faces.append(T_face)
        T = grid.from_faces(*faces)
    else:
        T = np.asarray(cell_temperatures, float)
    T = np.broadcast_to(T, (n_nodes - 1, grid.n_cells))
    state = initial_ribbon_state(geometry, n_nodes)
    programmed = programmed_shape(geometry, state, elasticity)
    rest = programmed.rest_shape(T, grid, transition)
    section = lce_ribbon_section(geometry, elasticity, thermal)
    node_mass, edge_inertia = lumped_masses(section, programmed.edge_length)
    fixed = statically_determinate_support(n_nodes, axis=0)
    g = np.array([0.0, 0.0, -STANDARD_GRAVITY]) if gravity else np.zeros(3)
    rod = DiscreteRod(section, rest, node_mass, edge_inertia, gravity=g, fixed=fixed)
    start = RestShape(programmed.edge_length, programmed.curvature, programmed.twist)
    result = solve_static(rod, state, increments=increments, rest_from=start)
    st = result.state
    geo = st.geometry()
    vor = 0.5 * (geo.length[:-1] + geo.length[1:])
    kappa = (
        material_curvatures(geo.e[:-1], geo.e[1:], geo.m1[:-1], geo.m2[:-1], geo.m1[1:], geo.m2[1:])
        / vor[:, None]
    )
    twist = geo.twist / vor
    inner = slice(len(vor) // 10, len(vor) - len(vor) // 10) if len(vor) >= 10 else slice(None)
    return StaticResponse(
        st,
        kappa,
        twist,
        float(geo.length.sum()),
        kappa[inner].mean(axis=0),
        float(twist[inner].mean()),
    )
