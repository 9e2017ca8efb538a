"""Searching (skills.following.searching), without a world: the search plan (the order of the
places visited, given where she vanished and her heading), walking round shelves, and the
robot working through a plan: looking along her heading, calling, on to the next place."""
from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

import follow_fakes
from follow_fakes import Pose, Speech, follower, track
from skills.following import GAVE_UP_REASON, SEARCHING
from skills.following.room import walking_distances
from skills.following.searching import (MAX_LOOKOUTS, Lookout, further_lookouts,
                                        search_plan)
from skills.navigation.gridmap import load_map

NORTH, SOUTH = math.pi / 2, -math.pi / 2
# a row of aisles (x = 5, 8, 11, 14, 17), their south ends at y = 6.5 and north ends at 16.5
ENDS = [(f"aisle{k}_{side}", 2.0 + 3 * k, y, th) for k in range(1, 6)
        for side, y, th in (("south", 6.5, NORTH), ("north", 16.5, SOUTH))]


def names(plan):
    return [lookout.why for lookout in plan]


def test_the_plan_starts_where_she_should_be_and_goes_on_along_her_way():
    # she walked north up aisle 4 (x = 14) and vanished 2.5 m short of its north end
    plan = search_plan((14.0, 15.5), (14.0, 14.0), (0.0, 1.0), ENDS, ahead=(14.0, 17.0))
    assert names(plan)[:2] == ["where she should be", "3 m on along her way"]
    assert plan[0].bearings == (NORTH,)                  # looking on along her heading
    # the aisle's north end lies within 1.5 m of where she should be: seen from there
    assert "aisle4_north" not in names(plan)
    # expanding outwards: the neighbouring aisles' north ends next, the end behind her later
    assert set(names(plan)[2:4]) == {"aisle3_north", "aisle5_north"}
    assert plan[2].bearings == (SOUTH,)                  # at an aisle end: into the aisle
    assert names(plan).index("aisle4_south") > names(plan).index("aisle5_north")
    assert len(plan) <= MAX_LOOKOUTS


def test_places_behind_her_count_for_more_than_places_ahead_at_the_same_distance():
    # in the front aisle (y = 5) between aisles 3 and 4, walking east
    ahead = search_plan((13.0, 5.0), (12.5, 5.0), (1.0, 0.0), ENDS)
    back = search_plan((12.0, 5.0), (12.5, 5.0), (-1.0, 0.0), ENDS)
    assert names(ahead)[1] == "aisle4_south" and names(back)[1] == "aisle3_south"
    # she stood: round in thirds where she should be, then simply nearest first
    stood = search_plan((12.5, 5.0), (12.5, 5.0), None, ENDS)
    assert stood[0].bearings is None
    assert names(stood)[1:3] in (["aisle3_south", "aisle4_south"], ["aisle4_south", "aisle3_south"])


def test_the_plan_counts_the_walk_round_shelves_and_leaves_out_what_is_too_far():
    # a place 3 m away as the crow flies but 12 m round a shelf comes after one 5 m away
    walk = {(14.0, 16.5): 5.0, (17.0, 16.5): 12.0, (11.0, 16.5): 6.0}
    plan = search_plan((14.0, 14.0), (14.0, 14.0), None,
                       [(n, x, y, th) for n, x, y, th in ENDS if (x, y) in walk],
                       walk=lambda x, y: walk.get((x, y)))
    assert names(plan) == ["where she should be", "aisle4_north", "aisle3_north", "aisle5_north"]
    none = search_plan((14.0, 14.0), (14.0, 14.0), None, ENDS[:1], walk=lambda x, y: None)
    assert names(none) == ["where she should be"]          # no way leads there


def test_her_course_breaks_the_tie_between_places_as_far_off_her_heading():
    # she walked north up aisle 4 to its north end: aisles 3 and 5 lie as far off her heading
    # and as far to walk; her trail as a whole went north-east (from the front aisle's west)
    east = search_plan((14.0, 16.5), (14.0, 16.5), (0.0, 1.0), ENDS, course=(0.6, 0.8))
    west = search_plan((14.0, 16.5), (14.0, 16.5), (0.0, 1.0), ENDS, course=(-0.6, 0.8))
    assert names(east)[1] == "aisle5_north" and names(west)[1] == "aisle3_north"


def test_once_the_plan_is_seen_the_search_expands_to_the_places_it_left_out():
    plan = search_plan((14.0, 15.5), (14.0, 14.0), (0.0, 1.0), ENDS, ahead=(14.0, 17.0))
    more = further_lookouts(plan, (14.0, 14.0), ENDS)
    planned = set(names(plan))
    assert more and not planned & set(names(more))
    assert set(names(more)) | planned >= {name for name, *_ in ENDS} - {"aisle4_north"}
    # nearest first, outwards from where she vanished
    distances = [math.hypot(q.x - 14.0, q.y - 14.0) for q in more]
    assert distances == sorted(distances)
    assert further_lookouts(plan + more, (14.0, 14.0), ENDS) == []   # nothing left: wait


def test_walking_distances_go_round_the_store_shelves():
    walk = walking_distances(load_map("store"), (14.0, 10.0))    # aisle A4, mid-way
    assert abs(walk(14.0, 16.5) - 6.5) < 0.3                       # straight up the aisle
    # aisle A5 is 3 m east through a shelf unit: round its south end, 3.5 + 3 + 3.5 m
    assert 9.5 <= walk(17.0, 10.0) <= 10.5
    assert walk(40.0, 10.0) is None                                # outside the store


def _she_walks_and_vanishes(following, perception, start, velocity, seconds, give_up_after):
    """Follow her for `seconds` walking from `start` (x, y) at `velocity` (vx, vy), sensed
    every 0.1 s from 0; then nobody is in view."""
    (x0, y0), (vx, vy) = start, velocity
    for k in range(int(round(seconds / 0.1)) + 1):
        t = 0.1 * k
        perception.believed = (track(1, x0 + vx * t, y0 + vy * t, t, vx=vx, vy=vy),)
        if k == 0:
            following.follow(0.0, target=1, give_up_after=give_up_after)
        following.sense(t)
    perception.believed = ()


def _she_walks_east_and_vanishes(following, perception, x0, y, give_up_after):
    """Follow her for 1 s walking east at 0.5 m/s from (x0, y); then nobody is in view."""
    _she_walks_and_vanishes(following, perception, (x0, y), (0.5, 0.0), 1.0, give_up_after)


def _lose_her_walking_east(following, perception, speech):
    _she_walks_east_and_vanishes(following, perception, 2.0, 0.0, give_up_after=12.0)
    now = 1.0
    while now < 1.0 + following.params.search_after + 0.05:
        now += 0.1
        following.sense(now)
    return now


def test_it_looks_along_her_heading_calls_goes_on_and_gives_up_naming_the_places():
    speech = Speech()
    following, perception = follower(speech)
    now = _lose_her_walking_east(following, perception, speech)
    assert following.state.phase == SEARCHING
    assert [text for _, text in speech.said] == [following.params.call]
    goal = following.motion.goal
    assert goal.kind == "turn_to" and abs(goal.bearing) < 0.2    # east, where she was going
    following.localization.state.th = goal.bearing
    while following._plan_index == 0:                    # looks a while, then on
        now += 0.1
        following.sense(now)
    assert now - 5.0 >= 1.5 - 0.1
    assert following._search_goal[0] > 2.5 + 2.5         # 3 m on along where she walked
    while following.state.phase == SEARCHING:
        now += 0.1
        following.localization.state.th = getattr(following.motion.goal, "bearing", 0.0) or 0.0
        following.sense(now)
    status = following.status
    assert status.failed and status.reason.startswith(GAVE_UP_REASON)
    assert "searched where she should be, 3 m on along her way" in status.reason


class Navigation(follow_fakes.Navigation):
    """follow_fakes' navigation on the store's map, with the phase a test sets ("blocked",
    with how long)."""

    def __init__(self):
        super().__init__(load_map("store"))
        self.state = SimpleNamespace(phase="idle", blocked_for=0.0, reason="")
        self.status = SimpleNamespace(status=None, failed=False)


def _searching_from(robot, plan_places):
    """A follower with a map searching a plan of `plan_places` (x, y), the robot at `robot`
    (x, y, heading) and nobody in view; she was last seen walking east at (12, 4.75)."""
    following, perception = follower(Speech())
    following.navigation = Navigation()
    _she_walks_east_and_vanishes(following, perception, 11.5, 4.75, give_up_after=60.0)
    following.localization.state = Pose(*robot)
    following._plan = [Lookout(x, y, (NORTH,), f"place{k}") for k, (x, y) in
                       enumerate(plan_places)]
    following._plan_index, following._searched, following._search_goal = 0, [], None
    following._viewed, following._view_t, following._way = {}, None, None
    following._lost_since = 1.0
    return following, perception


def _search_for(following, start, seconds):
    now = start
    while now < start + seconds:
        now += 0.1
        following.sense(now)
    return now


def test_a_place_in_view_is_looked_at_from_where_the_robot_is_and_passed():
    """Issue 23: reaching every place of the plan took one or two places in 30 s. A place
    within 3 m, in the detector's field and with the map's line to it clear is looked at from
    there; the search goes on to the next place without driving to it."""
    following, _ = _searching_from((12.0, 4.75, 0.0), [(12.5, 4.75), (14.0, 6.5), (20.0, 6.5)])
    _search_for(following, 5.0, 2.0)
    assert following.state.phase == SEARCHING
    assert following._searched[:2] == ["place0", "place1"]      # both in view from here
    assert following._plan_index == 2
    assert following._search_goal == (20.0, 6.5)


def test_a_place_behind_somebody_standing_in_the_line_of_sight_is_not_looked_at():
    following, perception = _searching_from((12.0, 4.75, 0.0), [(14.5, 4.75), (20.0, 6.5)])
    now = 5.0
    while now < 8.0:
        now += 0.1
        perception.believed = (track(7, 13.2, 4.8, now),)            # standing in the way
        following.sense(now)
    assert following._searched == [] and following._plan_index == 0
    assert following.navigation.goals                            # it drives on to the place


def test_a_place_the_robot_gets_no_nearer_is_passed_over_and_not_counted_as_searched():
    """Base seed 2 (issue 23): a shopper standing in an aisle held the search 25 s; navigation
    went from blocked to backing off and back, so its blocked clock never ran out. A place the
    robot has got no 0.3 m nearer for 5 s is passed over for the round."""
    following, _ = _searching_from((5.0, 4.75, math.pi), [(20.0, 6.5), (5.0, 16.5),
                                                           (8.0, 16.5)])
    following.navigation.state.phase = "blocked"
    now = _search_for(following, 5.0, 4.5)
    assert following._plan_index == 0
    now = _search_for(following, now, 1.0)
    assert following._plan_index == 1 and following._searched == []
    assert following._search_goal == (5.0, 16.5)


def _searching_map_ends(robot, names_):
    """A follower searching the store map's aisle ends `names_` (as the search plans them),
    the robot at `robot` (x, y, heading)."""
    following, perception = _searching_from(robot, [])
    ends = {name: (name, x, y, th) for name, x, y, th in following._lookouts()}
    following._plan = search_plan((12.0, 4.75), (12.0, 4.75), None,
                                  [ends[n] for n in names_], walk=lambda x, y: 1.0)[1:]
    return following


def test_an_aisle_end_counts_as_looked_at_only_when_the_robot_sees_into_the_aisle():
    """Fast seed 2 (issue 23): aisle A1's north end was passed from 2 m off in the back aisle
    (the mouth in view, the aisle behind the shelf corner) while she stood 2.5 m inside it."""
    beside = _searching_map_ends((6.9, 17.4, math.pi), ["aisle1_north", "aisle5_north"])
    _search_for(beside, 5.0, 2.0)
    assert beside._searched == [] and beside._plan_index == 0
    assert beside._search_goal == (5.0, 16.5)                 # it drives to the mouth
    above = _searching_map_ends((5.0, 18.0, -math.pi / 2), ["aisle1_north", "aisle5_north"])
    _search_for(above, 5.0, 2.0)
    assert above._searched == ["aisle1_north"]                # in view down the aisle


def test_an_aisle_behind_a_shelf_unit_or_a_display_is_not_looked_at_through_it():
    """The map draws a shelf unit's sides and the display closing aisle A6 one grid cell
    thick; a line of sight sampled every 0.1 m passed between their cells, so aisle A4 was
    looked at from A5's mouth through the shelf between them, and A6 from the back aisle
    through its display (fast seed 11, issue 23)."""
    next_aisle = _searching_map_ends((17.0, 16.5, SOUTH), ["aisle4_north"])
    _search_for(next_aisle, 5.0, 2.0)
    assert next_aisle._searched == []
    display = _searching_map_ends((20.0, 18.5, SOUTH), ["aisle6_north"])
    _search_for(display, 5.0, 2.0)
    assert display._searched == []
    down_it = _searching_map_ends((14.0, 17.0, SOUTH), ["aisle4_north"])
    _search_for(down_it, 5.0, 2.0)
    assert down_it._searched == ["aisle4_north"]         # seen from its own mouth


def test_a_dead_end_is_looked_at_up_the_aisle_not_at_its_closed_end():
    following, _ = _searching_from((11.0, 9.0, 0.0), [])
    ends = {name: th for name, x, y, th in following._lookouts()}
    assert abs(ends["aisle3_south"] - NORTH) < 1e-6          # the map's heading: south
    assert abs(ends["aisle6_north"] - SOUTH) < 1e-6          # the map's heading: north
    assert abs(ends["aisle4_south"] - NORTH) < 1e-6          # an open end keeps its heading


def test_the_further_places_include_where_shoppers_stand_visited_as_a_walk_from_the_robot():
    plan = search_plan((14.0, 15.5), (14.0, 14.0), (0.0, 1.0), ENDS, ahead=(14.0, 17.0))
    stops = [("shelf_a", 5.0, 10.0, 0.0), ("shelf_b", 17.0, 10.0, 0.0)]
    outwards = further_lookouts(plan, (14.0, 14.0), ENDS, stops=stops)
    walk = further_lookouts(plan, (14.0, 14.0), ENDS, stops=stops, start=(5.0, 5.0))
    assert {"shelf_a", "shelf_b"} <= set(names(walk)) and set(names(walk)) == set(names(outwards))

    def length(places):
        points = [(5.0, 5.0)] + [(q.x, q.y) for q in places]
        return sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(points, points[1:]))
    assert length(walk) < 0.8 * length(outwards)      # not to and fro across the store


def test_a_place_on_her_way_looked_at_without_her_leads_on_up_the_aisle_she_walked_into():
    """crowd20 seed 2 (issue 23): held in a crowd, the robot reached where she should be, at
    the south end of aisle A4, 15 s after she vanished walking up it; the detector sees 5 m
    of the 10 m aisle, she stood 7 m further up, and the plan turned back to the aisle's
    south end behind her. A place on her way looked at without her leads on along it, as far
    as she can have walked, up the aisle though her trail ran 11 degrees off its axis."""
    following, perception = follower(Speech())
    following.navigation = Navigation()
    following.localization.state = Pose(14.0, 4.75, NORTH)     # in the front aisle
    # she walks up aisle A4, a little east of north
    _she_walks_and_vanishes(following, perception, (14.0, 7.0), (0.1, 0.5), 2.0, 60.0)
    now = _search_for(following, 2.0, 4.5)
    assert following.state.phase == SEARCHING and following._plan_index == 0
    following._lost_since -= 12.0                              # as if held 12 s longer
    following.localization.state = Pose(14.2, 8.5, NORTH)      # at last where she should be
    _search_for(following, now, 2.0)
    lookout = following._plan[following._plan_index]
    assert lookout.why == "further along her way"
    assert abs(lookout.x - 14.2) < 0.5 and lookout.y > 15.0     # up the aisle, not into a shelf
    assert abs(lookout.bearings[0] - NORTH) < 0.1
    assert following._search_goal == (lookout.x, lookout.y)


def test_found_again_while_the_search_is_blocked_the_robot_drives_to_her_not_to_the_place():
    """Crowd5 seed 2 (issue 23, branch crowdfix1): navigation keeps its goal while its way is
    blocked (`Keeping._drive_to`), so when she was found again 1.7 m from the robot, standing,
    while the search's way to a place 9 m off was blocked, that place stayed navigation's goal
    for the 50 s left of the run. Found again, the goal is hers."""
    following, perception = _searching_from((12.0, 4.75, 0.0), [(20.0, 6.5), (5.0, 16.5)])
    now = _search_for(following, 5.0, 0.5)
    nav = following.navigation
    assert nav.goals[-1] == (20.0, 6.5) and following.state.phase == SEARCHING
    nav.state.phase = "blocked"                          # somebody stands in the search's way
    for _ in range(10):                                  # she stands 1.7 m off, in view
        now += 0.1
        her = track(following.state.target, 13.4, 5.7, now)
        perception.believed = (her,)
        following.sense(now)
    assert following.state.phase == "following"
    x, y = nav.goals[-1]
    assert math.hypot(x - her.x, y - her.y) < 0.5        # navigation drives to her


def test_the_place_on_along_her_way_is_up_the_aisle_she_turned_into_not_through_its_shelf():
    """Crowd10 seed 2 (issue 23, branch crowdfix1): she crossed the front aisle diagonally
    into aisle A4 (x = 14) and vanished as she turned up it; her heading still pointed
    north-east, and the place 3 m along it lay in aisle A5, beyond the shelf: the search went
    to A5 while she walked up A4. The place is where she can walk on, and it is looked at
    along that way."""
    following, perception = follower(Speech())
    following.navigation = Navigation()
    for k in range(41):                                  # 0.5 m/s north-east for 4 s
        t = 0.1 * k
        perception.believed = (track(1, 12.6 + 0.3 * t, 5.0 + 0.4 * t, t, vx=0.3, vy=0.4),)
        if k == 0:
            following.follow(0.0, target=1, give_up_after=60.0)
        following.sense(t)
    plan = following._make_plan((14.2, 7.0))
    ahead = next((lookout for lookout in plan if lookout.why == "3 m on along her way"), None)
    assert ahead is not None, [(lookout.why, lookout.x, lookout.y) for lookout in plan]
    assert abs(ahead.x - 14.0) < 0.8 and ahead.y > 8.5          # up aisle A4
    assert abs(ahead.bearings[0] - NORTH) < math.radians(20)    # looking on up it


def test_an_aisle_end_beside_where_she_should_be_is_planned_when_only_the_mouth_is_seen():
    """Crowd10 seed 0 (issue 23): she walked east along the back aisle (y = 16.8) past the
    north end of aisle A5 (x = 17) and turned down it. Where she should be, 1.2 m from that
    end, lies in the back aisle: from there a shelf's corner hides the aisle, so its end is
    planned as a place of its own, next after where she should be. From inside an aisle (the
    first test) its end is seen."""
    plan = search_plan((16.0, 17.1), (15.2, 16.8), (0.95, 0.3), ENDS)
    assert names(plan)[:2] == ["where she should be", "aisle5_north"]
    assert plan[1].bearings == (SOUTH,)                  # looking down the aisle


def test_her_heading_after_a_loss_is_taken_from_where_she_was_found_again():
    """Crowd10 seed 0 (issue 23): lost walking north up aisle A4, found again at its north
    end and lost 1.3 m on as she walked east along the back aisle. Her heading reached back
    across the loss to aisle A4 and pointed north: the search looked north of the back aisle
    and in aisle A4 while she walked on east. Her trail's points before the loss do not count
    for her heading."""
    following, perception = follower(Speech())
    for k in range(31):                                  # north up aisle A4 to y = 11.5
        t = 0.1 * k
        perception.believed = (track(1, 14.0, 10.0 + 0.5 * t, t, vy=0.5),)
        if k == 0:
            following.follow(0.0, target=1, give_up_after=60.0)
        following.sense(t)
    perception.believed = ()
    for k in range(1, 40):                               # lost for 4 s
        following.sense(3.0 + 0.1 * k)
    assert following.state.lost
    for k in range(27):                                  # found again: east along y = 16.8
        t = 10.0 + 0.1 * k
        perception.believed = (track(1, 13.9 + 0.5 * (t - 10.0), 16.8, t, vx=0.5),)
        following.sense(t)
    hx, hy = following._heading()
    assert abs(math.atan2(hy, hx)) < math.radians(10)    # east, not up aisle A4


def test_on_along_her_way_the_search_looks_into_each_aisle_she_may_have_turned_into():
    """Fast seed 11 (issue 23): she vanished walking west along the back aisle and turned down
    aisle A5. The place further along her way lay 10 m west, past A5's mouth 3 m aside: the
    robot drove past it and came back to it only after the next 10 m. Walking on along her
    way, the search looks into each aisle whose mouth it passes, in turn, going on along her
    way from abreast of each (the dead end A6, closed to the back aisle, is not one)."""
    following, perception = follower(Speech())
    following.navigation = Navigation()
    following.localization.state = Pose(26.0, 18.5, math.pi)
    # west along the back aisle, 0.5 m/s
    _she_walks_and_vanishes(following, perception, (25.0, 18.5), (-0.5, 0.0), 4.0, 120.0)
    now = _search_for(following, 4.0, 4.5)
    assert following.state.phase == SEARCHING and following._plan_index == 0
    following._lost_since -= 20.0                   # as if held 20 s longer
    where = following._plan[0]
    following.localization.state = Pose(where.x, where.y, math.pi)
    now = _search_for(following, now, 2.0)
    turning = following._plan[following._plan_index]
    assert (turning.why, turning.x, turning.y) == ("further along her way", 17.0, 16.5)
    assert turning.bearings == (SOUTH,)
    assert turning.into == pytest.approx((17.0, 14.5), abs=1e-9)        # down aisle A5
    assert abs(turning.way[0] - 17.0) < 0.3 and turning.way[1] > 17.5     # abreast of it
    assert following._search_goal == (17.0, 16.5)
    following.localization.state = Pose(17.0, 16.5, SOUTH)
    _search_for(following, now, 2.0)
    after = following._plan[following._plan_index]
    assert (after.why, after.x, after.y, after.bearings) == ("further along her way", 14.0,
                                                             16.5, (SOUTH,))
