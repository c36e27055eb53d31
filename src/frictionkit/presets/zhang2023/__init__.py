"""Seed 000 (Zhang et al., Actuators 2023): the two-axis differential micro-feed system (TDMS).

A ball screw whose screw (``theta1``) and nut (``theta2``) each have a motor; the worktable
moves at the *difference* of two fast rotations. This package holds (modules in brackets)

* the paper's Tables 2-8 in SI, with every correction recorded next to the value
  (:data:`PAPER_TABLES`, :func:`paper_stribeck`, :func:`paper_gms`) [``paper``];
* the simulated plant on the machine core (:func:`tdms_machine`, :func:`cdfs_machine`), its
  true friction (:class:`TrueFriction`, :func:`true_friction`) and every value the paper does
  not give as a named, validated assumption (:class:`Assumptions`) [``truth``, ``plant``];
* the virtual experiments of §5.2-5.4 (:func:`co_speed_sweep`, :func:`differential_sweep`,
  :func:`presliding_reciprocation`, :func:`memory_test`, :func:`sinusoidal_tracking`) returning
  :class:`TDMSRecording` objects, and the full closed loop of eqs. 15-16 with a feed-forward
  hook (:class:`FeedForward`, :func:`tracking_errors`) [``plant``, ``experiments``];
* the extension (ours): a conventional single-drive feed system (CDFS) against the TDMS at
  table speeds of 1-10 µm/s (:func:`crawling_comparison`) [``crawling``].

Observations a user of the virtual experiments should know (numbers from the plant):

* Co-speed runs are only *quasi*-stationary: the two loops lag differently while the speed
  changes, the table creeps by < 1 µm and the ball pair and guide keep a pre-sliding stress
  (~2-3 N each at the plateaus) that reaches both motors.
* The shaft supports relax after break-away with ``tau = T_S / C`` (Table 4's C in N/s):
  0.27-1.8 s; plateaus shorter than ~3 tau read friction above the steady map.
* The paper's direction-dependent GMS-3 (Table 4, ``paper_gms``) ratchets under µm
  reciprocation (the nut's force at +2 µm: 5.5 -> -36 N over four +-2 µm cycles); the truth
  uses one stiffness set per site for both directions.

Conventions (SI inside)
-----------------------
* **Linear-equivalent coordinates.** The paper prints shaft torques in N and shaft speeds in
  mm/s: they are linear-equivalent values at the lead ratio ``R = P_h / 2 pi``
  (``T [N·m] = R F [N]``, ``v [m/s] = R theta' [rad/s]``). The plant's shaft friction sites act
  on ``R theta1`` and ``R theta2`` (force in N, stiffness in N/m) so the tables enter as
  printed after unit conversion; motor torques are N·m (``K_t i_q``) and are converted with
  ``R`` at the edges (:func:`torque_to_force`).
* **Sign convention (§2.3).** Clockwise rotation of both motors: screw speed positive, nut
  speed negative. Co-rotation at equal speed is ``theta1' = -theta2'`` and holds the table
  still; the screw-nut relative rotation is ``theta1 + theta2`` and the table sits at
  ``x_t = R (theta1 + theta2) - e_g`` (eq. 13).
* **Table columns.** "Positive" = clockwise for both shafts (figure captions of Fig. 9), so
  the screw's positive column is ``theta1' > 0`` and the nut's positive column is
  ``theta2' < 0`` — Table 3 prints the nut's Stribeck velocity as ``-0.4858`` mm/s and the nut
  P-points of the clockwise run at negative angles, which confirms it.

Physics the plant derives (differs from eqs. 11-12)
----------------------------------------------------
The ball pair is one contact, so its axial force ``F_ax`` reacts on *both* shafts: the
generalised force of a force ``F`` acting at ``R (theta1 + theta2)`` is ``R F`` on each
shaft. The table load ``T_dt = R (M_t x_t'' + F_ft)`` therefore loads the driving shaft *and*
drives the other (in screw-driving mode it brakes the screw and pushes the nut along its
rotation), where eqs. 11-12 put it on the driving shaft only. The same holds for the ball
pair friction (the paper's "T_fbs decelerates the screw and accelerates the nut": equal
magnitudes ``R F_b`` here). The lumped per-motor friction of eq. 20 that WSIM identifies is
then ``T_s = T_fs + R (F_b + F_ft)`` and ``T_n = T_fn - R (F_b + F_ft)`` (nut speed negative).

Clearance ``e_g``
-----------------
THK's DIR series is an offset-preload nut: the preload removes the geometric clearance, so
``e_g`` of eq. 13 is modelled as the *elastic* lost motion of the preloaded ball pair, screw
shaft and support bearings under the axial force: the table is a degree of freedom joined to
``R (theta1 + theta2)`` by the axial spring ``k_axial`` (``e_g = F_ax / k_axial``). That
spring's force is the axial load that scales the ball pair's friction (:class:`NormalLoad`).

Provenance
----------
* Zhang et al., Actuators 2023 (seed 000): Tables 2-8 in SI with every correction next to the
  value (:data:`PAPER_TABLES`); every value the paper does not give is a field of
  :class:`Assumptions` with its reasoning.
"""


from .crawling import CrawlingResult, crawl_reference, crawling_comparison, velocity_ripple
from .experiments import (DT, MEMORY_TURNS, TrackingErrors, co_speed_sweep, differential_sweep, memory_test,
                          presliding_reciprocation, sinusoidal_tracking, tracking_errors, tracking_reference)
from .paper import PAPER_TABLES, R, force_to_torque, paper_gms, paper_stribeck, torque_to_force
from .plant import ENCODER_RESOLUTION, FeedForward, Reference, TDMSRecording, cdfs_machine, run_reference, tdms_machine
from .truth import Assumptions, TrueFriction, true_friction

__all__ = [
    "DT", "ENCODER_RESOLUTION", "MEMORY_TURNS", "PAPER_TABLES", "R", "Assumptions", "CrawlingResult", "FeedForward",
    "Reference", "TDMSRecording", "TrackingErrors", "TrueFriction", "cdfs_machine", "co_speed_sweep",
    "crawl_reference", "crawling_comparison", "differential_sweep", "force_to_torque", "memory_test", "paper_gms",
    "paper_stribeck", "presliding_reciprocation", "run_reference", "sinusoidal_tracking", "tdms_machine",
    "torque_to_force", "tracking_errors", "tracking_reference", "true_friction", "velocity_ripple",
]
