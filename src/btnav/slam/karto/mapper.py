"""Karto's Mapper as slam_toolbox runs it: match, link, close loops, optimise.

Each processed scan becomes a node of the pose graph: predicted from the odometry,
corrected by the sequential matcher against the running buffer, linked to the previous
node, the buffer and near chains, then loop closure against far chains and optimisation,
as Karto's. btnav departs only for bad odometry and ambiguous matches, each a named
constant measured in docs/decisions/0058: `RESCUE_BELOW_RESPONSE`, `FUSE_BELOW_RESPONSE`,
`OPEN_DIRECTION_GATE`, `LOOP_CLOSURE_GRAPH_WINDOW`, `LOOP_CLOSURE_MAX_ERROR_INCREASE`. A
Python loop here runs over graph nodes or chains, never over points or cells. The steps in
full: docs/decisions/0055.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field, replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ...core import fmath
from ...core.geometry import compose_arrays, normalize_angle
from ...params.localization import SlamToolboxParams
from ..graph.pose_graph import PoseGraph
from .covariance import inv3, largest_variance
from .odometry_fusion import FUSE_BELOW_RESPONSE, LEARN_ABOVE_RESPONSE, OdometryFusion
from .odometry_noise import OdometryNoise
from .scan_matcher import COVARIANCE_WINDOW, MatcherParams, MatchResult, ScanMatcher

F64 = NDArray[np.float64]

#: A sequential match whose response is below this is searched again over the loop
#: matcher's window (`Mapper._rescue`); Karto accepts every sequential match. Good
#: matches score 0.8-0.95 on the benchmark logs. The search window of the sequential
#: matcher (+-0.25 m around the odometry's guess with slam_toolbox's defaults) cannot
#: reach a pose the odometry misplaced by more: FR079's wheel odometry counts every
#: reversal as forward travel (21 times, 0.5-1 m off between processed scans), and a
#: match at the window's edge then bends the map (docs/decisions/0058-slam-benchmark-logs.md, FR079).
RESCUE_BELOW_RESPONSE = 0.7
#: ... and the wider search's match replaces it only when its response is higher by this.
RESCUE_MARGIN = 0.1
#: The wider search reaches this many times the distance the odometry says the robot
#: travelled since the last processed scan (plus the sequential window), not the loop
#: window's +-4 m: odometry wrong in direction but right in distance (FR079's reversals)
#: is off by at most twice the travel. Over +-4 m a scan in a corridor matches as well
#: 1-4 m along it: on the Freiburg hospital, whose odometry is good to 8 cm per relation,
#: 6 of its 10 replacements moved 1.1-3.7 m along corridors (relation errors 2-4 m).
RESCUE_TRAVEL_FACTOR = 2.0
#: ... and its coarse match must pass Karto's loop-closure tests (response above
#: `loop_match_minimum_response_coarse`) and be unambiguous: the largest variance of its
#: positional covariance (m^2, any direction) below this. FR079's replacements score
#: 0.0012-0.023 m^2; the hospital's wrong ones 0.23-30 m^2 (a corridor matches as well
#: anywhere along it; Karto's own `loop_match_maximum_variance_coarse`, 3 m^2 on x and y
#: alone, lets 0.2-1 m^2 through).
RESCUE_MAXIMUM_VARIANCE = 0.1
#: A loop closure's match moves the node only if it fits the chain better than the node
#: fits it where the graph already has it: the sequential matcher's fine search around
#: the node's graph pose (against the same chain) must score lower than the loop match
#: by more than Karto's covariance window (`COVARIANCE_WINDOW`: responses that close
#: count as equally good poses), else that match closes the loop instead. Karto takes the
#: best pose of the loop window (+-4 m with slam_toolbox's defaults, unpenalised) however
#: well the graph's own pose fits. In the Intel lab's rows of alike offices 5 of its 101
#: closures moved their node 0.4-1.2 m onto a look-alike 0.8-1.6 m from the truth
#: (responses 0.52-0.86) where the graph's pose, 5-9 cm from the truth for the first
#: three, scored 0.56-0.99: from 0.04 below to 0.29 above the loop match. The graph was
#: loose after a long loop, so the error test below let each through (rises of 0.8-15).
#: Of the right closures that moved a node more than 0.5 m, six beat the graph's pose by
#: 0.14-0.81; one by 0.01 (it then closes at the graph pose's match, 25 cm short). With
#: the test, Intel's relation error on the defaults is 3.6 cm instead of 5.7; windows
#: of 0.05 to 0.2 take the same decisions there.
LOOP_CLOSURE_GRAPH_WINDOW = COVARIANCE_WINDOW
#: A loop closure is taken back when, optimised with it, the graph's error (the sum of
#: r^T L r over the edges) is higher than before it by more than this: the closure's
#: squared Mahalanobis distance from where the graph puts the node. Karto accepts every
#: closure that passes the response and variance tests.
LOOP_CLOSURE_MAX_ERROR_INCREASE = 60.0
#: ... unless two chains of one node, both refused so, match it within this distance (m)
#: and heading (rad) of each other: then both close, untested. Taking out a large drift
#: raises the error as a wrong closure does (Intel's big loop: node 941 moved 2.6 m by
#: chains seen 200 and 600 s apart, responses 0.99, refused; a wrong chain moving it
#: 0.84 m passed and locked the drift in, refusing 30 right closures after it).
CLOSURE_AGREEMENT_DISTANCE = 0.2
CLOSURE_AGREEMENT_ANGLE = 0.05


def relative(a: F64, b: F64) -> F64:
    """Pose b in a's frame (a^-1 (+) b)."""
    s, c = fmath.sincos(float(a[2]))
    dx, dy = float(b[0] - a[0]), float(b[1] - a[1])
    return np.array([c * dx + s * dy, -s * dx + c * dy, normalize_angle(float(b[2] - a[2]))])


def compose(a: F64, b: F64) -> F64:
    return compose_arrays(np.asarray(a, float), np.asarray(b, float)[None, :])[0]


def rotate_covariance(cov: F64, yaw: float) -> F64:
    """A map-frame covariance in the frame of a node with heading `yaw` (Karto's LinkInfo)."""
    s, c = fmath.sincos(yaw)
    r = np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])
    return fmath.matmul_k(fmath.matmul_k(r, cov), r.T)


def weighted_mean(means: list[F64], covariances: list[F64]) -> F64:
    """Karto's ComputeWeightedMean: positions by inverse covariance, heading by mean direction."""
    inverses = [inv3(c) for c in covariances]
    total = inv3(sum(inverses[1:], inverses[0]))
    xy = np.zeros(3)
    for m, inv in zip(means, inverses, strict=True):
        xy = xy + fmath.matmul_k(fmath.matmul_k(total, inv), np.asarray(m, float)[:, None])[:, 0]
    s = sum(fmath.sin(float(m[2])) for m in means) / len(means)
    c = sum(fmath.cos(float(m[2])) for m in means) / len(means)
    return np.array([xy[0], xy[1], fmath.arctan2(s, c)])


def _agree(a: MatchResult, b: MatchResult) -> bool:
    """Two loop-closure matches of one scan that put it in the same place."""
    dx, dy = float(a.pose[0] - b.pose[0]), float(a.pose[1] - b.pose[1])
    return (
        dx * dx + dy * dy < CLOSURE_AGREEMENT_DISTANCE**2
        and abs(normalize_angle(float(a.pose[2] - b.pose[2]))) < CLOSURE_AGREEMENT_ANGLE
    )


@dataclass
class Scan:
    """One processed scan: what Karto's LocalizedRangeScan keeps."""

    stamp: float
    odom_pose: F64  # (3,) robot in the odom frame
    points: F64  # (N, 2) valid end points in the robot frame
    ranges: NDArray[np.float32]  # every reading, for the occupancy grid
    angles: F64  # beam angles in the sensor frame
    centroid: F64 = field(default_factory=lambda: np.zeros(2))  # mean point, robot frame


def matcher_params(p: SlamToolboxParams, loop: bool) -> MatcherParams:
    common = dict(
        range_threshold=p.max_laser_range,
        distance_variance_penalty=p.distance_variance_penalty,
        angle_variance_penalty=p.angle_variance_penalty,
        fine_search_angle_offset=p.fine_search_angle_offset,
        coarse_search_angle_offset=p.coarse_search_angle_offset,
        coarse_angle_resolution=p.coarse_angle_resolution,
        minimum_angle_penalty=p.minimum_angle_penalty,
        minimum_distance_penalty=p.minimum_distance_penalty,
        use_response_expansion=p.use_response_expansion,
    )
    if loop:
        return MatcherParams(
            search_space_dimension=p.loop_search_space_dimension,
            search_space_resolution=p.loop_search_space_resolution,
            smear_deviation=p.loop_search_space_smear_deviation,
            **common,
        )
    return MatcherParams(
        search_space_dimension=p.correlation_search_space_dimension,
        search_space_resolution=p.correlation_search_space_resolution,
        smear_deviation=p.correlation_search_space_smear_deviation,
        **common,
    )


class Mapper:
    """The graph of processed scans (see the module doc). `start_pose`: the first scan's
    robot pose in the map frame is `start_pose (+) odom_pose` (slam_toolbox's map_start_pose)."""

    def __init__(self, params: SlamToolboxParams, start_pose: ArrayLike = (0.0, 0.0, 0.0)):
        self.params = params
        self.start = np.asarray(start_pose, float)
        self.graph = PoseGraph()
        self.scans: list[Scan] = []
        self.running: list[int] = []
        self.sequential = ScanMatcher(matcher_params(params, loop=False))
        self.loop = ScanMatcher(matcher_params(params, loop=True))
        self._rescue_matchers: dict[int, ScanMatcher] = {}
        self.loop_closures = 0
        #: Loop closures Karto would accept that the graph refused (`_close`).
        self.loop_closures_refused = 0
        #: Sequential matches searched again over the loop window, and those replaced.
        self.rescues_tried = 0
        self.rescues = 0
        #: The odometry's noise, learnt from the well-supported sequential matches.
        self.odometry_noise = OdometryNoise()
        #: Sequential matches and that odometry, fused where it is surer (and counted).
        self.fusion = OdometryFusion(params, self.odometry_noise)
        #: Bumped whenever existing poses move (an optimisation): the map must be rebuilt.
        self.revision = 0
        #: Bumped whenever any node pose changes; keys the barycenter cache.
        self._pose_version = 0
        self._bary_key: tuple[PoseGraph, int, int] | None = None
        self._bary = np.zeros((0, 2))

    # -- views -------------------------------------------------------------------------------

    @property
    def poses(self) -> F64:
        """(K, 3) corrected robot poses of the processed scans in the map frame."""
        return self.graph.poses

    def world_points(self, i: int, pose: F64 | None = None) -> F64:
        p = self.graph.poses[i] if pose is None else pose
        return compose_arrays(
            p, np.column_stack([self.scans[i].points, np.zeros(len(self.scans[i].points))])
        )[:, :2]

    def barycenters(self) -> F64:
        """(K, 2) every scan's barycenter in the map frame, or its pose without
        `use_scan_barycenter` (Karto's reference positions), read-only; recomputed only
        after the poses change (a scan asks several times)."""
        if not self.scans:
            return np.zeros((0, 2))
        key = (self.graph, self.graph.num_nodes, self._pose_version)
        old = self._bary_key
        if old is None or old[0] is not key[0] or old[1:] != key[1:]:
            c = np.array([s.centroid for s in self.scans]) * self.params.use_scan_barycenter
            bary = compose_arrays(self.graph.poses, np.column_stack([c, np.zeros(len(c))]))
            self._bary = bary[:, :2]
            self._bary.flags.writeable = False
            self._bary_key = key
        return self._bary

    def _barycenter(self, pose: F64, scan: Scan) -> F64:
        """Karto's is the laser's pose without a barycenter; a node here is the robot's."""
        c = scan.centroid * self.params.use_scan_barycenter
        return compose(pose, np.array([c[0], c[1], 0.0]))[:2]

    def _reference(self, ids: list[int]) -> list[tuple[F64, F64]]:
        return [(self.world_points(i), self.graph.poses[i]) for i in ids]

    # -- processing --------------------------------------------------------------------------

    def predict(self, odom_pose: ArrayLike) -> F64:
        """The map pose of the robot at `odom_pose` by the last correction (Karto's Transform)."""
        odom = np.asarray(odom_pose, float)
        if not self.scans:
            return compose(self.start, odom)
        last = len(self.scans) - 1
        return compose(self.graph.poses[last], relative(self.scans[last].odom_pose, odom))

    def has_moved_enough(self, stamp: float, odom_pose: ArrayLike) -> bool:
        """Karto's HasMovedEnough on odometric poses (time, then heading, then distance)."""
        if not self.scans:
            return True
        last = self.scans[-1]
        p = self.params
        if stamp - last.stamp >= p.minimum_time_interval:
            return True
        d = relative(last.odom_pose, np.asarray(odom_pose, float))
        if abs(d[2]) >= p.minimum_travel_heading:
            return True
        return bool(d[0] ** 2 + d[1] ** 2 >= p.minimum_travel_distance**2 - 1e-9)

    def process(
        self,
        stamp: float,
        odom_pose: ArrayLike,
        points: F64,
        ranges: NDArray[np.float32],
        angles: F64,
    ) -> bool:
        """Add one scan (points: valid end points in the robot frame); False if not moved enough."""
        odom = np.asarray(odom_pose, float)
        if not self.has_moved_enough(stamp, odom):
            return False
        p = self.params
        pose = self.predict(odom)
        scan = Scan(stamp, odom, np.asarray(points, float), ranges, angles)
        if len(scan.points):
            scan.centroid = scan.points.mean(axis=0)
        covariance = np.eye(3)
        first = not self.scans
        if p.use_scan_matching and not first and len(scan.points):
            reference = self._reference(self.running)
            result = self.sequential.match(scan.points, pose, reference)
            d = relative(self.scans[-1].odom_pose, odom)
            if result.response >= LEARN_ABOVE_RESPONSE:
                self.odometry_noise.observe(d, relative(pose, result.pose))
            matched = result
            if result.response < RESCUE_BELOW_RESPONSE:
                travel = float(np.sqrt(d[0] * d[0] + d[1] * d[1]))
                result = self._rescue(scan.points, pose, reference, result, travel)
            if (
                result is matched
                and result.response < FUSE_BELOW_RESPONSE
                and self.odometry_noise.trusted
            ):
                pose, covariance = self.fusion.heading(pose, d, result)
            elif result is matched and self.odometry_noise.trusted:
                pose, covariance = self.fusion.open_direction(pose, d, result), result.covariance
            else:
                pose, covariance = result.pose, result.covariance
        self.scans.append(scan)
        node = self.graph.add_node(pose)
        if p.use_scan_matching:
            if not first:
                self._add_edges(node, pose, covariance)
            self._add_running(node)
            if p.do_loop_closing and len(scan.points):
                self._try_close_loop(node)
        return True

    def _rescue(
        self,
        points: F64,
        guess: F64,
        reference: list[tuple[F64, F64]],
        result: MatchResult,
        travel: float,
    ) -> MatchResult:
        """A sequential match with little support, searched again as a loop closure is
        (the loop matcher's coarse search, over a window `RESCUE_TRAVEL_FACTOR` x the
        odometry's `travel` wide each side, then the sequential matcher's fine search)
        against the same running scans; the better-supported of the two by at least
        `RESCUE_MARGIN` wins. btnav's, not Karto's: see `RESCUE_BELOW_RESPONSE`."""
        self.rescues_tried += 1
        coarse = self._rescue_matcher(travel).match(
            points, guess, reference, penalize=False, refine=False
        )
        if (
            coarse.response <= self.params.loop_match_minimum_response_coarse
            or largest_variance(coarse.covariance) >= RESCUE_MAXIMUM_VARIANCE
        ):
            return result
        fine = self.sequential.match(points, coarse.pose, reference, penalize=False)
        if fine.response < result.response + RESCUE_MARGIN:
            return result
        self.rescues += 1
        return fine

    def _rescue_matcher(self, travel: float) -> ScanMatcher:
        """The loop matcher with its window cut to +-(`RESCUE_TRAVEL_FACTOR` x travel +
        the sequential half window), in whole coarse steps; never wider than its own."""
        p = self.params
        step = 2.0 * p.loop_search_space_resolution  # the coarse lattice's spacing
        reach = RESCUE_TRAVEL_FACTOR * travel + 0.5 * p.correlation_search_space_dimension
        steps = math.ceil(reach / step - 1e-9)
        if 2.0 * steps * step >= p.loop_search_space_dimension:
            return self.loop
        matcher = self._rescue_matchers.get(steps)
        if matcher is None:
            loop = matcher_params(p, loop=True)
            matcher = ScanMatcher(replace(loop, search_space_dimension=2.0 * steps * step))
            self._rescue_matchers[steps] = matcher
        return matcher

    def _add_running(self, node: int) -> None:
        """Karto's AddRunningScan: cap the buffer by count and by span."""
        self.running.append(node)
        p = self.params
        poses = self.graph.poses
        while len(self.running) > 1:
            d = poses[self.running[0], :2] - poses[self.running[-1], :2]
            too_far = d[0] ** 2 + d[1] ** 2 > p.scan_buffer_maximum_scan_distance**2 - 1e-9
            if len(self.running) <= p.scan_buffer_size and not too_far:
                break
            self.running.pop(0)

    def _link(self, i: int, j: int, mean: F64, covariance: F64) -> None:
        """An edge i -> j measured as `mean` (j's map pose) with the matcher's covariance."""
        if j in self.graph.neighbours(i):
            return  # Karto keeps the first link between two scans
        frm = self.graph.poses[i]
        self.graph.add_edge(i, j, relative(frm, mean), rotate_covariance(covariance, float(frm[2])))

    def _link_chain(self, chain: list[int], node: int, mean: F64, covariance: F64) -> None:
        """Karto's LinkChainToScan: link the chain's scan closest to the node, if close enough."""
        bary = self.barycenters()
        ref = self._barycenter(self.graph.poses[node], self.scans[node])
        d2 = ((bary[chain] - ref) ** 2).sum(axis=1)
        k = int(np.argmin(d2))
        if d2[k] < self.params.link_scan_maximum_distance**2 + 1e-9:
            self._link(chain[k], node, mean, covariance)

    def _add_edges(self, node: int, pose: F64, covariance: F64) -> None:
        self._link(node - 1, node, pose, covariance)
        means, covs = [pose], [covariance]
        self._link_chain(self.running, node, pose, covariance)
        for chain in self._near_chains(node):
            if len(chain) < self.params.loop_match_minimum_chain_size:
                continue
            m = self.sequential.match(
                self.scans[node].points,
                self.graph.poses[node],
                self._reference(chain),
                penalize=False,
            )
            if m.response > self.params.link_match_minimum_response_fine - 1e-9:
                means.append(m.pose)
                covs.append(m.covariance)
                self._link_chain(chain, node, m.pose, m.covariance)
        if len(means) > 1:
            poses = self.graph.poses.copy()
            poses[node] = weighted_mean(means, covs)
            self.graph.set_poses(poses)
            self._pose_version += 1

    def _near_linked(self, node: int, max_distance: float) -> set[int]:
        """Karto's FindNearLinkedScans: breadth-first through the graph over scans whose
        barycenter lies within `max_distance` of the node's."""
        bary = self.barycenters()
        near = ((bary - bary[node]) ** 2).sum(axis=1) <= max_distance**2
        seen = {node}
        queue = deque([node])
        while queue:
            for j in self.graph.neighbours(queue.popleft()):
                if j not in seen and near[j]:
                    seen.add(j)
                    queue.append(j)
        return seen

    def _near_chains(self, node: int) -> list[list[int]]:
        """Karto's FindNearChains: runs of consecutive scans near the node around each
        near-linked scan; a run that reaches the node itself is not a chain."""
        dist = self.params.link_scan_maximum_distance
        bary = self.barycenters()
        near = ((bary - bary[node]) ** 2).sum(axis=1) < dist**2 + 1e-9
        done: set[int] = set()
        chains = []
        for k in sorted(self._near_linked(node, dist) - {node}):
            if k in done:
                continue
            lo, hi = k, k
            while lo - 1 >= 0 and near[lo - 1]:
                lo -= 1
            while hi + 1 < len(self.scans) and near[hi + 1]:
                hi += 1
            # Karto's walk stops at the first far scan; one that passes over the node
            # itself (always near) marks the chain invalid.
            chain = list(range(lo, hi + 1))
            done.update(chain)
            if not lo <= node <= hi:
                chains.append(chain)
        return chains

    def _next_loop_chain(self, node: int, start: int) -> tuple[list[int], int]:
        """Karto's FindPossibleLoopClosure from scan `start`: the first run of consecutive scans
        within `loop_search_maximum_distance`, cut after its last near-linked scan, that is at
        least `loop_match_minimum_chain_size` long and followed by a far scan; and where the
        next search starts. Runs are found with array operations, not a walk over scans."""
        p = self.params
        bary = self.barycenters()[start:]
        ref = self._barycenter(self.graph.poses[node], self.scans[node])
        near = ((bary - ref) ** 2).sum(axis=1) < p.loop_search_maximum_distance**2 + 1e-9
        linked = np.zeros(len(near), bool)
        ids = [i - start for i in self._near_linked(node, p.loop_search_maximum_distance)]
        linked[[i for i in ids if i >= 0]] = True
        edges = np.flatnonzero(np.diff(np.concatenate([[0], near.astype(np.int8), [0]])))
        for lo, hi in zip(edges[::2], edges[1::2], strict=True):
            cut = np.flatnonzero(linked[lo:hi])
            chain = range(lo + cut[-1] + 1 if cut.size else lo, hi)
            if hi < len(near) and len(chain) >= p.loop_match_minimum_chain_size:
                return [start + i for i in chain], start + int(hi)
        return [], len(self.scans)

    def _try_close_loop(self, node: int) -> bool:
        p = self.params
        closed = False
        points = self.scans[node].points
        refused: list[tuple[list[int], MatchResult]] = []
        chain, start = self._next_loop_chain(node, 0)
        while chain:
            ref = self._reference(chain)
            coarse = self.loop.match(
                points, self.graph.poses[node], ref, penalize=False, refine=False
            )
            if (
                coarse.response > p.loop_match_minimum_response_coarse
                and coarse.covariance[0, 0] < p.loop_match_maximum_variance_coarse
                and coarse.covariance[1, 1] < p.loop_match_maximum_variance_coarse
            ):
                fine = self.sequential.match(points, coarse.pose, ref, penalize=False)
                if fine.response >= p.loop_match_minimum_response_fine:
                    fine = self._against_graph(node, ref, fine)
                    if self._close(node, [(chain, fine)]):
                        closed = True
                    else:
                        agreed = next((r for r in refused if _agree(r[1], fine)), None)
                        if agreed is None:
                            refused.append((chain, fine))
                        else:
                            self._close(node, [agreed, (chain, fine)], gate=False)
                            refused.remove(agreed)
                            self.loop_closures_refused -= 2
                            closed = True
            chain, start = self._next_loop_chain(node, start)
        return closed

    def _against_graph(
        self, node: int, reference: list[tuple[F64, F64]], match: MatchResult
    ) -> MatchResult:
        """The loop match, unless the fine match around the node's graph pose (against the
        same chain) is as good within `LOOP_CLOSURE_GRAPH_WINDOW`: then that one (btnav's,
        not Karto's: see there)."""
        here = self.sequential.match(
            self.scans[node].points, self.graph.poses[node], reference, penalize=False
        )
        if here.response >= match.response - LOOP_CLOSURE_GRAPH_WINDOW:
            return here
        return match

    def _close(
        self, node: int, matches: list[tuple[list[int], MatchResult]], *, gate: bool = True
    ) -> bool:
        """Karto's loop closure (the node moved to the first match, linked to each
        match's chain, the graph optimised), taken back when `gate` and the optimised
        graph's error grew by more than `LOOP_CLOSURE_MAX_ERROR_INCREASE` (btnav's, not
        Karto's: see there)."""
        before = self.graph.poses.copy()
        edges = self.graph.num_edges
        error = self.graph.error()
        self._set_pose(node, matches[0][1])
        for chain, fine in matches:
            self._link_chain(chain, node, fine.pose, fine.covariance)
        report = self.graph.optimize()
        self._pose_version += 1
        if gate and report.final_error - error > LOOP_CLOSURE_MAX_ERROR_INCREASE:
            while self.graph.num_edges > edges:
                self.graph.pop_edge()
            self.graph.restore_poses(before)
            self.loop_closures_refused += len(matches)
            return False
        self.loop_closures += len(matches)
        self.revision += 1
        return True

    def _set_pose(self, node: int, match: MatchResult) -> None:
        poses = self.graph.poses.copy()
        poses[node] = match.pose
        self.graph.set_poses(poses)
        self._pose_version += 1
