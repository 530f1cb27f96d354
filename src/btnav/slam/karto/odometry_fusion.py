"""A sequential match and the mapper's learnt odometry, fused where the odometry is surer.

btnav's, not Karto's: Karto takes every sequential match alone. The mapper learns its
odometry's noise from the well-supported matches (`OdometryNoise`); a poorly supported
match is fused with the odometry's prediction in all three dimensions (`heading`), a
well-supported one along the one direction the scan leaves open, a corridor's length
(`open_direction`). Each is gated so that where the odometry is no surer than the
matcher can resolve the match stands, bit for bit Karto's: a nudge there changes which
loop closures pass (the constants below say where that was measured).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.geometry import normalize_angle
from ...params.localization import SlamToolboxParams
from .covariance import inv3, largest_variance
from .odometry_noise import OdometryNoise
from .scan_matcher import MatchResult

F64 = NDArray[np.float64]

#: A sequential match below this response (`RESCUE_BELOW_RESPONSE`'s: poorly supported)
#: that the wider search did not replace is fused with the odometry's prediction, by
#: their covariances (`OdometryFusion.heading`), the odometry's learnt from the log
#: (`OdometryNoise`). Karto takes the match alone, and on the Freiburg hospital, whose
#: odometry drifts 0.3 degrees per metre, matches of response 0.2-0.5 in corridors turned
#: the map by 6-20 degrees (relation errors over the whole tour 281 cm, fused 58 cm;
#: over the local relations 11.08 and 10.13 cm).
FUSE_BELOW_RESPONSE = 0.7
#: ... where the odometry's heading variance is below this share of the match's (its
#: standard deviation under half): where they are comparable the fusion moves a node by
#: a degree or so for little gain, and that is enough to change which loop closures
#: pass (Freiburg 079: a 1.4-degree fusion at 1987 s refused the closure to 1226 s,
#: 6.82 -> 13.16 cm; with this test 6.96 cm)...
ODOMETRY_RATIO = 0.25
#: ... and only for odometry that, by the learnt model, turns less over a straight step
#: of `minimum_travel_distance` (one node's travel) than this many fine angular steps of
#: the matcher (`fine_search_angle_offset`: 0.2 degrees with slam_toolbox's defaults):
#: odometry surer of the heading than the matcher can resolve. Elsewhere Karto's match
#: stands alone: a fusion's nudge of a degree or so changes which loop closures pass,
#: and Karto's closure decisions are not robust to that (Intel: two fusions of 1.5 and
#: 0.5 degrees at nodes 619 and 857 let a closure 3 m wrong through at node 939, 3.61 ->
#: 7.08 cm; FR079 6.84 -> 7.06 from two, ACES from three). Learnt over each benchmark
#: log once trusted (`OdometryNoise.trusted`), in degrees per 0.5 m: the hospital
#: 0.143-0.147, ACES 0.36-0.68, Freiburg 079 0.43-0.72, Intel 1.7-2.2, MIT CSAIL 1.9-6.2.
#: With `minimum_travel_distance` 0 (scans on time only) every odometry passes.
ODOMETRY_FINE_STEPS = 1.0
#: ... and unless they disagree beyond this chi-square (3 dof, 99%): the match is kept.
ODOMETRY_GATE = 11.34
#: A sequential match at or above this response teaches `OdometryNoise` (good matches
#: score 0.8-0.95 on the benchmark logs).
LEARN_ABOVE_RESPONSE = 0.8
#: A well-supported match (response at least `FUSE_BELOW_RESPONSE`; not replaced) is
#: fused with the odometry along the direction its positional covariance is widest, the
#: one the scan leaves most open (a corridor's length), where the odometry is clearly
#: surer there (its learnt positional variance at most `ODOMETRY_RATIO` of the match's)
#: and the two agree within this chi-square (1 dof, 99%); across that direction, and in
#: heading, the match stands (`OdometryFusion.open_direction`). Karto takes the best pose
#: of a response that is flat along a corridor up to noise: on the corridor loop
#: (tests/slam/karto/test_slam_loop.py) Karto's standard deviation along the corridor is 8-17
#: cm where the odometry's error is 0.5 cm a step, and at seed 9 the matches of nodes
#: 30-34 slid the lap 18 cm along the lower corridor (2-8 cm each; node ATE 12.1 cm, 3.6
#: with every match's error along its corridor taken out; 2.6 fused). Only the position
#: moves: the edge keeps Karto's covariance, as every other edge does (Karto's
#: covariances overstate the matcher's errors about 7 times alike in x, y and heading,
#: on all ten seeds; the odometry's learnt variance along the corridor would make that
#: edge 7 times stiffer there than across, and a loop closure's correction then goes
#: into headings: seed 5 8.0 cm and 94% of the occupied cells within 10 cm of a wall
#: with it, 5.6 cm and 99.8% without).
#: Requiring the direction to be open (the variance across it under a quarter of the
#: variance along) was tried: seeds 3 and 5 then miss the map bound (94.6%, 94.8%).
#: Only for odometry that, by its learnt model, measures one node's travel
#: (`minimum_travel_distance`) better than the coarse search's lattice step (twice
#: `correlation_search_space_resolution`: 2 cm), as `ODOMETRY_FINE_STEPS` asks of its
#: heading: the corridor loop's learns 1.1 cm, the benchmark logs' 2-3 cm. Without this
#: test the fusion also ran on those logs and moved which loop closures pass (Intel 3.61
#: -> 4.81 cm, Freiburg 079 6.84 -> 7.20, MIT CSAIL 3.50 -> 3.64); with it they are as
#: before.
OPEN_DIRECTION_GATE = 6.63


class OdometryFusion:
    """The two fusions, with what they did: matches fused (`heading_fusions`,
    `open_direction_fusions`) and kept alone because the two disagreed (`*_refused`)."""

    def __init__(self, params: SlamToolboxParams, noise: OdometryNoise) -> None:
        self.params = params
        self.noise = noise
        self.heading_fusions = 0
        self.heading_fusions_refused = 0
        self.open_direction_fusions = 0
        self.open_direction_fusions_refused = 0

    def heading(self, prediction: F64, increment: F64, result: MatchResult) -> tuple[F64, F64]:
        """A poorly supported match and the odometry's `prediction` (`increment` since the
        last node) fused by their covariances (a Kalman update): the odometry's from its
        learnt noise (`OdometryNoise`), the match's with its heading variance widened to
        the coarse search's spread (`MatchResult.heading_variance`: Karto's angular
        covariance sees only the fine search's +-1 degree, so a scan that fits about as
        well 10 degrees off looks certain). The match alone is kept where the odometry
        turns more per step than the matcher resolves (`ODOMETRY_FINE_STEPS`), is not
        clearly surer of the heading than the match (`ODOMETRY_RATIO`) or the two
        disagree (`ODOMETRY_GATE`). The fused covariance is the edge's to the previous node."""
        p = self.params
        per_metre = self.noise.per_unit()[0]
        if (
            per_metre * p.minimum_travel_distance
            >= ODOMETRY_FINE_STEPS * p.fine_search_angle_offset
        ):
            return result.pose, result.covariance
        odo = self.noise.covariance(increment)
        match = np.array(result.covariance, float)
        match[2, 2] = result.heading_variance  # (never below Karto's angular variance)
        if odo[2, 2] > ODOMETRY_RATIO * match[2, 2]:
            return result.pose, result.covariance
        delta = np.asarray(result.pose, float) - prediction
        delta[2] = normalize_angle(float(delta[2]))
        s_inv = inv3(odo + match)
        chi2 = float(fmath.matmul_k(delta[None, :], fmath.matmul_k(s_inv, delta[:, None]))[0, 0])
        if chi2 > ODOMETRY_GATE:
            self.heading_fusions_refused += 1
            return result.pose, result.covariance
        self.heading_fusions += 1
        gain = fmath.matmul_k(odo, s_inv)
        pose = prediction + fmath.matmul_k(gain, delta[:, None])[:, 0]
        pose[2] = normalize_angle(float(pose[2]))
        cov = odo - fmath.matmul_k(gain, odo)
        return pose, 0.5 * (cov + cov.T)

    def open_direction(self, prediction: F64, increment: F64, result: MatchResult) -> F64:
        """The match's pose with its position along the direction of its largest positional
        variance (the unit eigenvector u of Karto's covariance, eigenvalue `lam`) fused
        with the odometry's `prediction` (`increment` since the last node): a Kalman
        update on u . (x, y) alone, the odometry's variance `r` there from its learnt
        noise (`OdometryNoise`, isotropic in position). Across u and in heading the match
        stands. The match alone is kept unless the odometry is clearly surer along u
        (`r` at most `ODOMETRY_RATIO` x `lam`) and the two agree (`OPEN_DIRECTION_GATE`).
        btnav's, not Karto's: see `OPEN_DIRECTION_GATE`."""
        p = self.params
        per_metre = self.noise.per_unit()[2]
        if per_metre * p.minimum_travel_distance >= 2.0 * p.correlation_search_space_resolution:
            return result.pose  # not surer of a step's travel than the coarse lattice's step
        cov = result.covariance
        a, b, c = float(cov[0, 0]), float(cov[0, 1]), float(cov[1, 1])
        lam = largest_variance(cov)
        if abs(b) > 1e-12:  # (A - lam I) u = 0: u along (lam - c, b)
            u = np.array([lam - c, b])
        else:
            u = np.array([1.0, 0.0]) if a >= c else np.array([0.0, 1.0])
        u = u / math.sqrt(float(u @ u))
        r = float(self.noise.covariance(increment)[0, 0])
        if r > ODOMETRY_RATIO * lam:
            return result.pose
        along = float(u @ (np.asarray(prediction[:2], float) - np.asarray(result.pose[:2], float)))
        if along * along > OPEN_DIRECTION_GATE * (lam + r):
            self.open_direction_fusions_refused += 1
            return result.pose
        self.open_direction_fusions += 1
        pose = np.array(result.pose, float)
        pose[:2] += lam / (lam + r) * along * u
        return pose
