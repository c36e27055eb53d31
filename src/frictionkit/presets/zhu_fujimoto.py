"""Seed 001 preset: Zhu & Fujimoto, ball-screw-driven stage in the zero-speed region.

Every value names where it comes from. Three kinds of entry:

* **paper** — printed in seed 001 (table, equation, figure or section given);
* **correction** — a printed value we read differently, with the reason;
* **assumption** — the paper is silent; a catalogue or textbook value chosen *before*
  running any reproduction (never tuned until a finding appeared).

All values are SI. Linear-equivalent friction levels use the screw ratio
``R = L_p / (2 pi)`` [m/rad] to convert motor torques [N·m] to forces at the nut [N].

Corrections to the paper
------------------------
* ``B_m`` (Table 1) is printed 1.1772 N·m·s/rad. With it the motor alone would need
  ~97 N·m of viscous torque at the 157 mm/s peak speed of the §5 reference, 12x the
  whole-axis viscosity B = 0.1 N·m·s/rad identified in eq. 1 (Fig. 2). Read as
  1.1772e-3 N·m·s/rad (exponent lost, like ``J_m``'s ``10^-3``), the Table 1 viscosities
  add up to ``B_m + B_b + C_t R^2 = 0.088`` N·m·s/rad, consistent with B = 0.1.
* ``sigma = 2`` in §5.3 (eq. 5) is printed without a unit; ``x/sigma`` is dimensionless
  and ``x`` is a displacement, so we read 2 µm (same reading as ``models/rolling.py``).
* eq. 7 prints the friction force, not its compensation (sign flipped; see
  ``models/rolling.py``).
* ``F0`` is printed in N·m: a motor-side torque (Fig. 13: 2.431; §5.3: 2.65).

Two stages: Table 1 or the measured response (``stage=``)
--------------------------------------------------------
Table 1 gives a motor-side inertia ``J_m + J_b + M_t R^2 = 4.3e-3`` kg·m², while the
inertia identified from the measured frequency response (eq. 1, Fig. 2) is ``J = 0.01``
kg·m². The controller is designed on eq. 1 in both stages, as the paper does.

* ``"table1"`` — every inertia as printed in Table 1. This stage contradicts two of the
  paper's *measurements*: its current -> motor-angle response lies 6.2-7.2 dB above the
  Fig. 2 fit over 5-50 Hz, and in the fast reversal of §5 its motor input keeps the sign of
  the motion until zero speed, where Fig. 5(b) shows it changing sign before (both
  measured by ``reproduce.zhu_fujimoto``, see the README "Reproductions" table).
* ``"fig2"`` (**default**) — calibrated to the paper's measured response: the missing inertia
  ``J_n - (J_m + J_b + M_t R^2) = 5.7e-3`` kg·m² is put on the motor side
  (:data:`J_m_FIG2` = 8.0e-3), so the rigid-body inertia equals the identified ``J = 0.01``.
  Only this one Table 1 entry changes; the table mass and the screw (eq. 2, Fig. 7) keep their
  printed values. Its Fig. 2 level is within 1 dB of the fitted line (-0.2 to +0.1 dB) and its
  motor input reverses before zero speed in the fast reversal, as Fig. 5(b) shows.

Why ``"fig2"`` is the default: the paper's findings are measurements on the rig whose
response Fig. 2 measures and eq. 1 fits, and its controller (PTC, DOB) is built on that fit. A
stage that reproduces the measured response and the measured sign change of Fig. 5(b) is the
better stand-in for that rig than one that follows a parameter table whose inertias do not add
up to the measurement (Table 1's ``J_m`` is most likely the bare rotor; couplings, hubs and the
encoder are not listed). The calibration has no free parameter — ``J_m`` follows from the
paper's own identified ``J`` (eq. 1) — and nothing is tuned towards a finding.
Where the missing inertia sits is an assumption: on the motor, where the only unlisted parts
(coupling hub, encoder, brake) are. On the table instead (``M_t`` = 1835 kg) the first
anti-resonance / resonance fall to 54 / 98 Hz (the response drops to -12 dB of the fit
within 5-50 Hz) and the paper's controller rings (88 µm in every Table 3 law, quick run),
so that reading contradicts both the measured response and the paper's working controller.
The default is chosen on the measurements of the rig (Fig. 2, the input of Fig. 5(b)), not
on the compensation results: of those, each stage reproduces some the other does not
(``"table1"``: Fig. 5's degradation after a fast deceleration; ``"fig2"``: Table 3's order).
``"table1"`` stays available (``frictionkit reproduce zhu-fujimoto --stage table1``); the
README table and the demo report give every finding for both stages.

Provenance
----------
* Zhu & Fujimoto, "High-precision control for ball-screw-driven stage in zero-speed region"
  (seed 001): every value cites its table, equation, figure or section; what the paper does
  not give is a named assumption in this module.
"""

from __future__ import annotations

import math

# --------------------------------------------------------------------------- paper
#: Table 1 — motor inertia [kg·m²].
J_m = 2.3e-3
#: Table 1 as printed [N·m·s/rad]; see :data:`B_m` for the value used.
B_m_PRINTED = 1.1772
#: Correction of Table 1 ``B_m`` (see module docstring) [N·m·s/rad].
B_m = 1.1772e-3
#: Table 1 — ball-screw length [m].
L_b = 1.169
#: Table 1 — ball-screw mass [kg].
M_b = 9.3526
#: Table 1 — ball-screw inertia [kg·m²].
J_b = 1.0052e-3
#: Table 1 — ball-screw viscosity [N·m·s/rad].
B_b = 5.0e-2
#: Table 1 — lead [m/rev].
L_p = 1.2e-2
#: Table 1 — table mass [kg].
M_t = 273.0
#: Table 1 — linear-guide viscosity [N·s/m].
C_t = 1.0e4
#: Screw ratio (rotation to translation) ``R = L_p / 2 pi`` [m/rad] (§3.3).
R = L_p / (2.0 * math.pi)

#: Eq. 1 — torque constant [N·m/A].
K_tau = 0.715
#: Eq. 1 — identified nominal inertia [kg·m²].
J_n = 0.01
#: Eq. 1 — identified nominal viscosity [N·m·s/rad].
B_n = 0.1

#: Calibration to eq. 1 / Fig. 2 (stage ``"fig2"``) — motor-side inertia [kg·m²] that makes
#: the plant's rigid-body inertia ``J_m + J_b + M_t R^2`` equal the identified ``J_n``
#: (= 7.999e-3; Table 1's 2.3e-3 plus the 5.7e-3 the table does not list).
J_m_FIG2 = J_n - J_b - M_t * R**2
#: Stages of the elastic plant (module docstring): Table 1 inertias, or calibrated to Fig. 2.
STAGES = ("table1", "fig2")
#: Default stage (module docstring, "Why fig2 is the default").
STAGE = "fig2"

#: §2.1 — absolute encoder, pulses per revolution.
ENCODER_COUNTS = 2**20
#: §2.1 — linear-scale resolution [m].
SCALE_RESOLUTION = 100e-9

#: §2.2 — control period of PID, DOB and friction compensation [s].
T_CONTROL = 0.5e-3
#: §2.2 — PTC (reference) frame period [s].
T_PTC = 1.0e-3
#: §2.2 — closed-loop bandwidth of the pole-placement PID [Hz].
BANDWIDTH_HZ = 20.0
#: §2.2 — DOB first-order low-pass cut-off [Hz].
DOB_CUTOFF_HZ = 80.0

#: Fig. 13 — measured rolling-friction level (motor torque) [N·m].
F0_MEASURED = 2.431
#: §5.3 — F0 used by all three compensators [N·m].
F0_COMPENSATION = 2.65
#: Fig. 13 / §5.3 — pre-sliding length of the sinc law [m].
XS = 10e-6
#: §5.3 — sigmoid transition length (correction: unit µm, see docstring) [m].
SIGMA = 2e-6
#: §5 — reference ``25 (1 - cos 2 pi t)`` mm: amplitude [m] and period [s].
REF_AMPLITUDE = 25e-3
REF_PERIOD = 1.0

#: Table 3 — maximum tracking error during the reverse motion [µm].
TABLE3_UM = {"sinc": 4.24, "coulomb": 5.44, "sigmoid": 1.65}

# ---------------------------------------------------------------------- assumptions
#: Assumption — Young's modulus of bearing steel [Pa] (textbook, 206 GPa).
E_STEEL = 206e9
#: Assumption — shear modulus of steel [Pa] (textbook, 79.3 GPa).
G_STEEL = 79.3e9
#: Derived — equivalent solid-shaft diameter of the screw from Table 1,
#: ``J_b = M_b d^2 / 8`` -> ``d = sqrt(8 J_b / M_b)`` = 29.3 mm (root-diameter-like).
SCREW_DIAMETER = math.sqrt(8.0 * J_b / M_b)
#: Assumption — nut at mid-stroke: fraction of ``L_b`` from the motor-side bearing.
NUT_POSITION = 0.5
#: Assumption — disc/bellows coupling torsional stiffness [N·m/rad]; catalogue range for
#: couplings rated 20-60 N·m is 1e4-3e4 N·m/rad, lower end taken.
K_COUPLING = 1.5e4
#: Derived from the assumptions above — screw torsional stiffness motor -> nut,
#: ``G (pi d^4 / 32) / (NUT_POSITION L_b)`` [N·m/rad].
K_SCREW_TORSION = G_STEEL * (math.pi * SCREW_DIAMETER**4 / 32.0) / (NUT_POSITION * L_b)
#: Derived — axial stiffness of the screw between the left bearing and the nut,
#: ``E (pi d^2 / 4) / (NUT_POSITION L_b)`` [N/m]; the right part likewise.
K_SCREW_AXIAL_LEFT = E_STEEL * (math.pi * SCREW_DIAMETER**2 / 4.0) / (NUT_POSITION * L_b)
K_SCREW_AXIAL_RIGHT = E_STEEL * (math.pi * SCREW_DIAMETER**2 / 4.0) / ((1.0 - NUT_POSITION) * L_b)
#: Assumption — axial stiffness of each support-bearing set [N/m]: preloaded
#: angular-contact pair for a 30 mm screw end (catalogue ~750 N/µm, DF pair).
K_BEARING = 7.5e8
#: Assumption — screw-ball-nut axial stiffness [N/m]: preloaded double nut, 32 mm
#: diameter, 12 mm lead (catalogue 700-1100 N/µm at 10 % Ca preload; 800 N/µm taken).
K_NUT = 8.0e8
#: Assumption — structural damping ratio of the first elastic mode (steel feed drives
#: 1-5 %); stiffness-proportional (Rayleigh) damping on every spring.
DAMPING_RATIO = 0.02
#: Assumption — Coulomb level of the linear guide [N]: four preloaded size-35 blocks,
#: friction coefficient 0.003 on ~20 kN preload + 2.7 kN weight (68 N) + seal drag
#: (~5 N per block) ≈ 90 N, rounded to 100 N.
GUIDE_FRICTION = 100.0
#: Assumption — the rest of the measured rolling friction (Fig. 13, 2.431 N·m) sits at
#: the nut (preload drag, incl. support bearings), as a torque opposing screw rotation
#: [N·m].
NUT_FRICTION_TORQUE = F0_MEASURED - GUIDE_FRICTION * R
#: Assumption — each friction site is a Dahl element whose transition from ``-Fc`` to
#: ``0.9 Fc`` spans the measured pre-sliding length ``XS`` (Figs. 12-13):
#: ``sigma0 = ln(20) Fc / XS``.
PRESLIDING_LENGTH = XS
#: Assumption — current limit [A]: ~1.5 kW servo with Kτ = 0.715 N·m/A, 3x peak.
I_MAX = 30.0
#: Assumption — white measurement noise before quantisation: encoder [counts] and
#: linear scale [m] (interpolation noise of a 100 nm scale, ~20 nm rms).
ENCODER_NOISE_COUNTS = 0.5
SCALE_NOISE = 20e-9
#: Assumption — PID derivative low-pass at 10x the closed-loop bandwidth [Hz].
DERIVATIVE_CUTOFF_HZ = 200.0
#: Assumption — plant sub-steps per control period (50 µs): the stiff linear part is
#: discretised exactly, the sub-step only sets how often the friction states update.
N_SUBSTEPS = 10

# ------------------------------------------- nut model "flank" (assumptions, fixed a priori)
# Chosen from catalogue values before the flank model was first run; consistent with the
# K_NUT assumption above (32 mm, 12 mm lead preloaded double nut at 10 % Ca).
#: Assumption — ball-centre (nominal) diameter of the screw [m], as in the K_NUT line.
BALL_CENTER_DIAMETER = 32e-3
#: Derived — tangent of the lead angle, ``L_p / (pi d0)`` (= 0.119).
TAN_LEAD_ANGLE = L_p / (math.pi * BALL_CENTER_DIAMETER)
#: Assumption — basic dynamic load rating Ca of that double nut [N] (catalogue 30-40 kN for
#: 32 mm x 12 mm lead, 2.5 turns x 2 circuits per half; 35 kN taken).
NUT_DYNAMIC_LOAD_RATING = 35e3
#: Assumption — per-flank ball preload ``P`` [N]: 10 % Ca, the preload the K_NUT catalogue
#: stiffness refers to.
NUT_PRELOAD = 0.10 * NUT_DYNAMIC_LOAD_RATING
#: Catalogue (THK/NSK/HIWIN ball-screw technical data) — preload drag torque of a
#: preloaded nut ``T_p = K P L_p / (2 pi)`` with ``K = 0.05 / sqrt(tan beta)`` (= 0.145):
#: linear-equivalent friction ``K P`` at the nut.
PRELOAD_TORQUE_COEFFICIENT = 0.05 / math.sqrt(TAN_LEAD_ANGLE)
#: Derived — flank friction coefficient ``mu_f`` [N per N of flank ball load]: the drag
#: ``K P`` shared by the two flank sets each carrying ``P`` at zero external load,
#: ``mu_f = K / 2``. Flank friction at ``F_bn = 0``: ``2 mu_f P = K P`` (507 N, 0.97 N·m);
#: the rest of NUT_FRICTION_TORQUE (support bearings, seals, recirculation) stays
#: load-independent.
FLANK_FRICTION_COEFFICIENT = PRELOAD_TORQUE_COEFFICIENT / 2.0
# ------------------------------------------- nut model "hertz" (assumptions, fixed a priori)
# The "flank" friction sites on a preloaded Hertzian ball contact (two flank sets, each
# F = c delta^1.5). No new number: preload NUT_PRELOAD (10 % Ca = 3.5 kN) and the net
# stiffness at zero external load dF_bn/dd(0) = K_NUT (the catalogue stiffness is that of
# the preloaded nut, both sets in parallel) fix
#   d0 = 3 P / K_NUT = 13.1 µm (preload deflection of each set), c = P / d0^1.5;
# one set unloads beyond |F_bn| = 2^1.5 P = 9.9 kN. Fixed before the first "hertz" run.

#: Nut friction models available (see :class:`frictionkit.plants.ballscrew.ElasticBallScrew`);
#: the preset default stays the original ``"sliding"``.
NUT_MODELS = ("sliding", "flank", "hertz")
NUT_MODEL = "sliding"

#: The assumed stiffnesses varied ±30 % in the robustness tests (names of
#: :class:`frictionkit.plants.ballscrew.ElasticBallScrew` fields).
ASSUMED_STIFFNESSES = ("k_coupling", "k_torsion", "k_axial", "k_bearing", "k_nut")

#: Reproduction choices (not in the paper): window of "the reverse motion" around a
#: reversal [s] and the ``l_d`` evaluation window ``T_p`` [s].
REVERSAL_WINDOW = (-0.05, 0.10)
LD_WINDOW = 10e-3
#: Reproduction choice — window around the zero-speed point [s] for the comparisons on the
#: trapezoidal Fig. 10 references (Fig. 5, Table 2's redesigned stop): their acceleration
#: corners sit 50.7 ms either side of zero speed in the fast cases, and the jerk transient of
#: a corner (same in every case, ~2.4 µm) is not the zero-speed effect being compared.
ZERO_SPEED_WINDOW = (-0.04, 0.045)
#: Fig. 10 cases: cruise speed [m/s] and deceleration [m/s²] of slow and fast motions.
#: Fast = the §5 reference's peak deceleration 100 pi^2 mm/s^2; slow = 1/20 of it.
LD_SPEED = 50e-3
LD_FAST_DECEL = 100.0 * math.pi**2 * 1e-3
LD_SLOW_DECEL = LD_FAST_DECEL / 20.0
#: Reproduction choice — Table 2's redesigned fast non-reverse stop
#: (:func:`frictionkit.control.zero_speed.pattern_i_stop_segments`): share of the guide friction
#: ``f_g`` the drive force keeps in the direction of motion at rest (final deceleration
#: ``(1 - margin) f_g / M_t``). Half, a round design margin, not tuned.
REDESIGN_MARGIN = 0.5


def plant_kwargs(nut_model: str = NUT_MODEL, stage: str = STAGE) -> dict:
    """Keyword arguments of :class:`~frictionkit.plants.ballscrew.ElasticBallScrew` for this stage.

    ``nut_model = "flank"`` adds the flank load-transfer nut friction (NUT_PRELOAD,
    FLANK_FRICTION_COEFFICIENT); ``"hertz"`` the same on the preloaded Hertzian contact;
    ``"sliding"`` is the original model. ``stage``: ``"fig2"`` (default, motor inertia
    :data:`J_m_FIG2`) or ``"table1"`` (:data:`J_m`); see the module docstring.
    """
    if stage not in STAGES:
        from ..errors import ParameterError

        raise ParameterError(f"stage = {stage!r}: must be one of {STAGES}")
    extra = {}
    if nut_model in ("flank", "hertz"):
        extra = dict(nut_model=nut_model, nut_preload=NUT_PRELOAD,
                     flank_friction_coefficient=FLANK_FRICTION_COEFFICIENT)
    elif nut_model != "sliding":
        from ..errors import ParameterError

        raise ParameterError(f"nut_model = {nut_model!r}: must be one of {NUT_MODELS}")
    return dict(
        J_m=J_m_FIG2 if stage == "fig2" else J_m, B_m=B_m, J_b=J_b, B_b=B_b, M_b=M_b, M_t=M_t, C_t=C_t, L_p=L_p, K_tau=K_tau,
        k_coupling=K_COUPLING, k_torsion=K_SCREW_TORSION,
        k_axial=K_SCREW_AXIAL_LEFT, k_axial_right=K_SCREW_AXIAL_RIGHT,
        k_bearing=K_BEARING, k_nut=K_NUT, damping_ratio=DAMPING_RATIO,
        guide_friction=GUIDE_FRICTION, nut_friction=NUT_FRICTION_TORQUE / R,
        presliding_length=PRESLIDING_LENGTH, **extra,
    )

#: Assumption — which sensor feeds the PID (§2.2 does not say). P and I act on the
#: linear-scale position (the stage is what must track), D on the motor encoder
#: ("dual" feedback, usual in machine tools). Chosen for stability, not for a finding: a
#: PID with all three terms on the scale (full-closed) limit-cycles at the current limit on
#: this chain (non-collocated first mode ~166 Hz), checked with friction switched off.
FEEDBACK = "dual"
