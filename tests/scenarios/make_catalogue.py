"""Draws the ASCII maps of the scenario catalogue and writes the YAML files beside this script.

Run it after changing a scenario here; the YAML files are what the tests and the CLI read.
"""
import os, textwrap
OUT = os.path.dirname(os.path.abspath(__file__))

class G:
    def __init__(self, w, h):
        self.w, self.h = w, h
        self.g = [["." for _ in range(w)] for _ in range(h)]
        self.rect(0, 0, w - 1, h - 1, "#", outline=True)
    def set(self, x, y, ch):
        self.g[self.h - 1 - y][x] = ch
    def fill(self, x0, y0, x1, y1, ch):
        for x in range(min(x0, x1), max(x0, x1) + 1):
            for y in range(min(y0, y1), max(y0, y1) + 1):
                self.set(x, y, ch)
    def rect(self, x0, y0, x1, y1, ch, outline=False):
        for x in range(x0, x1 + 1):
            self.set(x, y0, ch); self.set(x, y1, ch)
        for y in range(y0, y1 + 1):
            self.set(x0, y, ch); self.set(x1, y, ch)
    def text(self):
        return "\n".join("".join(r) for r in self.g)

def write(name, description, g, body, resolution=0.1, unknown=None):
    art = textwrap.indent(g.text(), "    ")
    doc = f"name: {name}\ndescription: >\n{textwrap.indent(textwrap.fill(description, 96), '  ')}\n"
    doc += (f"map:\n  resolution: {resolution}\n" + (f"  unknown: {unknown}\n" if unknown else "")
            + f"  ascii: |\n{art}\n"
            + textwrap.dedent(body).strip() + "\n")
    path = os.path.join(OUT, name + ".yaml")
    if os.path.exists(path):   # keep the measured known issues written below the scenario
        old = open(path).read()
        if "\nknown_issue:" in old:
            doc += old[old.index("\nknown_issue:") + 1:]
    with open(path, "w") as f:
        f.write(doc)

# 1. phantom obstacle in the doorway behind the robot
g = G(70, 24)
g.fill(30, 1, 31, 22, "#"); g.fill(30, 7, 31, 16, "P")   # wall with a 1.0 m doorway full of phantom
write("phantom_obstacle",
      "A stale obstacle fills the doorway behind the robot: it is in the costmaps but not in the "
      "world, and the laser (240 degrees, facing away) cannot see through it. No plan exists until "
      "a recovery clears the costmap or turns the laser toward the doorway.",
      g, """
      start: [4.5, 1.2, 0.0]
      goals: [[1.2, 1.2, 3.1416]]
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 2. corridor blocked for good by an object the map does not know
g = G(60, 14)
write("corridor_blocked", "A corridor blocked for good by a cabinet the map does not know. There is no "
      "way through: the robot must give up cleanly and never touch the cabinet.", g, """
      start: [0.8, 0.7, 0.0]
      goals: [[5.2, 0.7, 0.0]]
      objects:
        - {box: [3.0, 0.1, 3.3, 1.3]}
      time_limit: 90
      expect:
        outcome: failed
        reason: NO_VALID_PATH        # the planner's reason, not the controller's patience
        max_time: 60
        no_collision: true
      """)

# 3. person blocking a corridor who leaves after 10 s
g = G(70, 30)
g.fill(1, 13, 45, 28, "#"); g.fill(55, 13, 68, 28, "#")   # corridor y 0.1..1.2, alcove x 4.6..5.4 north
write("person_in_corridor", "A person stands in the corridor and steps into an alcove after 10 s. "
      "Waiting (or recovering until the way is free) gets the robot through without touching them.",
      g, """
      start: [0.8, 0.7, 0.0]
      goals: [[6.3, 0.7, 0.0]]
      moving:
        - {radius: 0.25, waypoints: [[3.0, 0.65], [5.0, 0.65], [5.0, 2.5]], speed: 0.5, start_time: 10.0}
      time_limit: 90
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 4. goal inside an obstacle
g = G(50, 40)
g.fill(30, 15, 36, 22, "#")
write("goal_in_obstacle", "The goal lies inside a pillar. No plan can reach it: the robot must "
      "fail cleanly without driving into the pillar.", g, """
      start: [1.0, 2.0, 0.0]
      goals: [[3.3, 1.9, 0.0]]
      time_limit: 90
      expect:
        outcome: failed
        reason: [GOAL_OCCUPIED, NO_VALID_PATH]
        max_time: 30                 # not circling the pillar until the time limit
        no_collision: true
      """)

# 5. goal inside an obstacle, carrot planner: get as close as possible
write("goal_in_obstacle_carrot", "The goal lies inside a pillar, and the robot runs carrot_planner, "
      "which walks back from the goal along the line to the robot to the first reachable pose "
      "(tuning guide 2.1.1): it gets next to the pillar and stops there.", g, """
      start: [1.0, 1.9, 0.0]
      goals: [[3.3, 1.9, 0.0]]
      params:
        move_base: {base_global_planner: carrot_planner/CarrotPlanner}
      time_limit: 40
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 6. goal in the -x direction (guide problem 2)
g = G(60, 40)
write("goal_minus_x", "The goal lies in the -x direction of the map (tuning guide, Problems 2): the "
      "robot must turn around and get there as surely as in +x.", g, """
      start: [4.5, 2.0, 0.0]
      goals: [[1.0, 2.0, 3.1416]]
      time_limit: 40
      expect:
        outcome: succeeded
        no_collision: true
        max_time: 30
      """)

# 7. thin pole missing from the map (guide problem 3)
g = G(70, 26)
write("thin_pole", "A thin vertical pole (4 cm) that the map does not hold stands on the straight "
      "line to the goal (tuning guide, Problems 3). The laser must see it and the robot pass it "
      "without touching it.", g, """
      start: [0.8, 1.3, 0.0]
      goals: [[6.0, 1.3, 0.0]]
      objects:
        - {circle: [3.5, 1.3, 0.02]}
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 8. unknown box in a corridor: replan around
g = G(70, 34)
write("unknown_box", "A box the map does not know stands in the middle of a wide corridor. The "
      "robot sees it with its laser and goes around.", g, """
      start: [0.8, 1.7, 0.0]
      goals: [[6.2, 1.7, 0.0]]
      objects:
        - {box: [3.0, 1.3, 3.6, 2.1]}
      time_limit: 45
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 9. dead end: only backing off helps. Drawn at 5 cm a character: the bay is 0.65 m wide, less
# than the body's diagonal (0.67 m), so the robot really cannot turn in it (the earlier 0.7 m bay
# left room to turn on the spot). The robot starts in it: a local planner on an inflated costmap
# (DWA, as in ROS) cannot drive into a bay narrower than its turning circle by itself (the
# corridor of non-inscribed cells along its middle is one 5 cm cell wide), so it was pushed or
# driven in by hand.
g = G(96, 60)
g.fill(66, 1, 89, 23, "#"); g.fill(66, 37, 89, 58, "#")   # bay x 3.3..4.5, y 1.20..1.85
g.fill(90, 1, 94, 58, "#")
write("dead_end_backoff", "The robot stands at the end of a dead-end bay barely wider than itself "
      "(0.65 m for a 0.50 x 0.44 m body whose diagonal is 0.67 m), facing the closed end, with "
      "its goal behind it. It cannot turn in the bay and its local planner never drives "
      "backwards (min_vel_x 0, the ROS default): rotating is impossible, and only backing out "
      "gets it free.", g, """
      start: [3.95, 1.525, 0.0]
      goals: [[0.8, 1.525, 3.1416]]
      params:
        DWAPlannerROS: {min_vel_x: 0.0}
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
      expect_by_tree:
        # rotate blocked: TemporaryGoal backs straight out of the bay on its own clear arc
        smach_recovery: {recoveries_fired: [TemporaryGoal], max_time: 40}
      """, resolution=0.05)

# 10. rotate recovery impossible next to a wall
g = G(60, 30)
write("rotate_blocked_near_wall", "The robot starts alongside a wall, 5 cm from it, with its goal "
      "behind it. Turning in place would sweep its corners through the wall, so rotate_recovery "
      "is impossible; the robot has to move away from the wall first.", g, """
      start: [3.0, 0.37, 0.0]
      goals: [[1.0, 1.5, 3.1416]]
      time_limit: 45
      expect:
        outcome: succeeded
        no_collision: true
      expect_by_tree:
        # rotate blocked: TemporaryGoal backs away from the wall on a gentle, clear arc
        smach_recovery: {recoveries_fired: [TemporaryGoal], max_time: 40}
      """)

# 11. narrow gap that needs a longer sim_time
g = G(60, 40)
g.fill(30, 1, 31, 38, "#"); g.fill(30, 25, 31, 32, ".")   # gap 0.8 m, y 2.5..3.3, off the straight line
write("narrow_gap_sim_time", "A 0.8 m gap in a wall, off the straight line to the goal, with the "
      "longer sim_time the tuning guide recommends for narrow passages (3.0 s; guide 3.1.2). The "
      "guide's claim does not hold in this simulator with the planner's correct defaults: over "
      "seeds 0-4 move_base gets through on all five with 1.0 s, 1.5 s or the default 1.7 s, and "
      "on one with 3.0 s (seed 2) or 4.0 s (seed 0); its long arcs cut the corner toward the "
      "wall post and it gets stuck there. With 3.0 s smach_recovery gets through on two of seeds "
      "0-4 (0 and 4; elsewhere its recoveries keep returning it to the post until the time runs "
      "out). A good tree gets through whatever the horizon: a tree that does not carries a "
      "known issue.", g, """
      start: [1.0, 1.0, 0.0]
      goals: [[5.0, 1.0, 0.0]]
      params:
        DWAPlannerROS: {sim_time: 3.0}
      time_limit: 60
      expect:
        # what a good tree does whatever the horizon: gets through the gap (see known_issue)
        outcome: succeeded
        no_collision: true
      """)

# 12. tight final approach. The goal pose must fit: the earlier bay was 0.5 m deep with the goal
# 0.2 m from its end, which put the 0.5 m body's front 5 cm into the end wall.
g = G(60, 40)
g.fill(42, 1, 58, 15, "#"); g.fill(42, 24, 58, 38, "#"); g.fill(50, 16, 58, 23, "#")  # bay x 4.2..5.0, y 1.6..2.4
write("tight_final_approach", "The goal is at the end of a bay 0.8 m wide and 0.8 m deep, facing "
      "into it, off to the side of the start: the robot has 18 cm on either side and 15 cm in "
      "front of it at the goal. Following the path closely at first and then weighting the goal "
      "(the near-goal reconfigure of the tuning guide section 7) gets it in without touching "
      "the sides.", g, """
      start: [1.0, 1.0, 0.0]
      goals: [[4.6, 2.0, 0.0]]
      time_limit: 30
      expect:
        outcome: succeeded
        no_collision: true
        max_time: 20
      """)

# 13. doorway entered at a bad angle (guide problem 4)
g = G(60, 50)
g.fill(30, 1, 31, 48, "#"); g.fill(30, 30, 31, 39, ".")   # door 1.0 m, y 3.0..4.0
write("doorway_bad_angle", "The robot starts hugging the wall beside a doorway, facing along the "
      "wall, so it must enter the doorway at a sharp angle (tuning guide, Problems 4).", g, """
      start: [2.5, 4.6, -1.5708]
      goals: [[4.5, 3.0, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
      """)

# 14. doorway oscillation
g = G(50, 40)
g.fill(25, 1, 26, 38, "#"); g.fill(25, 16, 26, 23, ".")    # 0.8 m door
write("doorway_oscillation", "A narrow doorway (0.8 m) straight ahead, approached at an angle: "
      "the situation where a local planner's best trajectory can flip between the door posts "
      "(move_base's oscillation_timeout case). With DWA's correct defaults (path_distance_bias "
      "32, goal_distance_bias 24) the robot does not oscillate here: both trees drive through "
      "in about 8 s without a recovery. The turning on the spot this scenario was built for came "
      "from the 0.6 / 0.8 biases bug. A narrower door (0.6 m, tried) does not bring the "
      "oscillation back: neither tree gets through it. The scenario stays as a check that a "
      "door with 18 cm to spare on either side of the 0.44 m wide body is passed cleanly.", g, """
      start: [1.0, 1.5, 0.3]
      goals: [[4.0, 2.5, 0.0]]
      time_limit: 40
      expect:
        outcome: succeeded
        no_collision: true
        max_time: 20
        recoveries_not_fired: [TemporaryGoal]
      """)

# 15. laser drop-out
g = G(70, 20)
write("laser_dropout", "The laser stops for 3 s mid-corridor. The safety gate stops the robot on the "
      "stale scan; navigation carries on when scans return.", g, """
      start: [0.8, 1.0, 0.0]
      goals: [[6.2, 1.0, 0.0]]
      faults:
        - {kind: laser_dropout, start: 4.0, duration: 3.0}
      time_limit: 45
      expect:
        outcome: succeeded
        no_collision: true
      """)


# ============================================================================ v2 catalogue
# Each states what a good tree must do (docs/scenarios.md, "The catalogue"); a shipped tree that
# misses one carries a known_issue with the measured reason (written by the measurement, not here).
def room(w, h):
    return G(w, h)

# stale obstacles that leave a long detour open: a phantom in the short doorway, a long way round
g = G(80, 40)
g.fill(40, 1, 41, 38, "#"); g.fill(40, 16, 41, 24, "P")          # wall x 4.0, doorway y 1.6..2.5
g.fill(11, 28, 38, 29, "#"); g.fill(43, 28, 68, 29, "#")         # a corridor along the top, open
g.fill(40, 30, 41, 38, ".")                                       # at both ends: the long way
write("stale_doorway_long_detour",
      "A stale obstacle (a person who has left) still fills the doorway in both costmaps. The "
      "only other way is a corridor round the top, four times longer. A good tree notices that its "
      "plan is much longer than the map-only route and clears or looks again before driving it "
      "(it starts facing away, so the laser has not seen the doorway): it goes through it.", g, """
      start: [2.0, 2.0, 3.1416]
      goals: [[6.0, 2.0, 0.0]]
      time_limit: 90
      expect:
        outcome: succeeded
        avoid: [{box: [3.0, 3.0, 5.0, 4.0], name: top_corridor}]
        via: [{box: [3.9, 1.6, 4.3, 2.5], name: doorway}]
        max_time: 45
      """)

g = G(80, 40)
g.fill(40, 1, 41, 38, "#"); g.fill(40, 6, 41, 11, ".")            # doorway y 0.6..1.1 ... wider:
g.fill(40, 5, 41, 12, "."); g.fill(40, 5, 41, 12, "P")
g.fill(40, 30, 41, 37, ".")                                        # long way: top gap
write("stale_gap_global_only",
      "A stale obstacle sits in the near gap of the global costmap only (the local costmap never "
      "held it). A far gap is open. A good tree takes the near gap after clearing, not the far one.",
      g, """
      start: [2.0, 0.9, 3.1416]
      goals: [[6.0, 0.9, 0.0]]
      phantoms:
        - {box: [3.9, 0.4, 4.3, 1.4], costmap: global}
      time_limit: 90
      expect:
        outcome: succeeded
        avoid: [{box: [3.5, 2.9, 4.5, 3.9], name: far_gap}]
        max_time: 45
      """)

# goals changed while a recovery runs
g = G(70, 24)
g.fill(30, 1, 31, 22, "#"); g.fill(30, 7, 31, 16, "P")
write("goal_changed_during_recovery",
      "The way to the first goal is blocked by a stale obstacle, so recoveries start. Half a "
      "second into the first one that lasts (a clear is over at once) the operator sends a new "
      "goal the other way. The new goal must pre-empt the "
      "recovery at once (within a control period or two) and the robot drive to it.", g, """
      start: [4.5, 1.2, 0.0]
      goals: [[1.2, 1.2, 3.1416]]
      events:
        - {name: new_goal, at: {while_recovery: any, delay: 0.5}, goal: [6.2, 1.2, 0.0]}
      time_limit: 60
      expect:
        outcome: succeeded
        goals_reached: 1
        preempt_within: 0.5
        final_pose: {of: [6.2, 1.2, 0.0], within: 0.3}
      """)

g = G(60, 30)
write("goal_replaced_mid_route",
      "Half way to its goal the robot is given another goal at right angles. It must drive to the "
      "new one, not finish the old one first.", g, """
      start: [0.8, 0.8, 0.0]
      goals: [[5.0, 0.8, 0.0]]
      events:
        - {name: redirect, at: 4.0, goal: [2.5, 2.4, 1.5708]}
      time_limit: 40
      expect:
        outcome: succeeded
        goals_reached: 1
        final_pose: {of: [2.5, 2.4, 1.5708], within: 0.3}
        avoid: [{box: [4.0, 0.1, 5.9, 1.5], name: old_goal_area}]
      """)

write("goal_added_while_driving",
      "A second goal is added while the robot drives to the first: it visits both, in order.", g, """
      start: [0.8, 0.8, 0.0]
      goals: [[4.5, 0.8, 0.0]]
      events:
        - {name: second, at: 3.0, add_goal: [4.5, 2.2, 3.1416]}
      time_limit: 60
      expect:
        outcome: succeeded
        goals_reached: 2
        final_pose: {within: 0.3}
      """)

# sensor faults
g = G(70, 20)
write("laser_dropout_stops_robot",
      "The laser stops for 4 s mid-corridor. From half a second after the drop-out until the scans "
      "return the robot must stand still (no motion on stale data), then carry on to the goal.",
      g, """
      start: [0.8, 1.0, 0.0]
      goals: [[6.2, 1.0, 0.0]]
      events:
        - {name: drop, at: 3.0, fault: {kind: laser_dropout}}
        - {name: back, at: 7.0, end_fault: laser_dropout}
      time_limit: 45
      expect:
        outcome: succeeded
        stopped: [{from: {event: drop, delay: 0.8}, until: back, v: 0.02, w: 0.05}]
      """)

g = G(70, 20)
write("laser_frozen_box_appears",
      "The laser freezes (fresh stamps, the same ranges) for 5 s and during that time a box is put "
      "in the robot's way. A good stack notices that the scan no longer changes while the robot "
      "moves and stops rather than drive into what it cannot see.", g, """
      start: [0.8, 1.0, 0.0]
      goals: [[6.2, 1.0, 0.0]]
      events:
        - {name: freeze, at: 2.0, fault: {kind: laser_frozen, duration: 5.0}}
        - {name: box, at: 2.5, add: {box: [3.2, 0.2, 3.5, 1.8], name: cart}}
        - {name: box_gone, at: 12.0, remove: cart}
      time_limit: 60
      expect:
        outcome: succeeded
      """)

write("odometry_slip",
      "The wheels slip for 6 s (only 40 % of their turning moves the robot). Navigation must carry "
      "on and get there, without a recovery fired by a stall that is not one.", g, """
      start: [0.8, 1.0, 0.0]
      goals: [[6.2, 1.0, 0.0]]
      faults:
        - {kind: odom_slip, start: 2.0, duration: 6.0, slip: 0.6}
      time_limit: 60
      expect:
        outcome: succeeded
        max_time: 40
      """)

write("blocked_rotation_at_start",
      "The robot is wedged for 5 s and cannot turn, with the goal behind it. It must not drive "
      "off blindly or collide; once it can turn it gets there.", g, """
      start: [3.5, 1.0, 0.0]
      goals: [[0.9, 1.0, 3.1416]]
      faults:
        - {kind: blocked_rotation, start: 0.0, duration: 5.0}
      time_limit: 60
      expect:
        outcome: succeeded
        max_time: 40
      """)

write("stuck_wheel_mid_route",
      "The left wheel stops for 3 s mid-route: the robot pivots about it. It must not touch the "
      "walls of the 2 m corridor and must still reach the goal.", g, """
      start: [0.8, 1.0, 0.0]
      goals: [[6.2, 1.0, 0.0]]
      faults:
        - {kind: stuck_wheel, start: 3.0, duration: 3.0, wheel: left}
      time_limit: 60
      expect:
        outcome: succeeded
      """)

# dynamic obstacles
g = G(70, 30)
write("person_crossing",
      "A person crosses the robot's path back and forth. The robot gets to the goal without "
      "touching them.", g, """
      start: [0.8, 1.5, 0.0]
      goals: [[6.2, 1.5, 0.0]]
      moving:
        - {radius: 0.25, waypoints: [[3.5, 0.4], [3.5, 2.6]], speed: 0.4, loop: true}
      time_limit: 60
      expect:
        outcome: succeeded
      """)

g = G(80, 32)
write("person_head_on",
      "A person walks towards the robot down the middle of a 3 m corridor and stops in its way. "
      "The robot must pass them with no contact.", g, """
      start: [0.8, 1.6, 0.0]
      goals: [[7.2, 1.6, 0.0]]
      moving:
        - {radius: 0.25, waypoints: [[6.5, 1.6], [5.0, 1.6]], speed: 0.5, start_time: 1.0}
      time_limit: 60
      expect:
        outcome: succeeded
      """)

g = G(80, 22)
write("cart_pushed_into_path",
      "A cart is pushed into the corridor in front of the robot, then taken away 8 s later. The "
      "robot must not hit it, and must get to the goal once it has gone (or round it).", g, """
      start: [0.8, 1.1, 0.0]
      goals: [[7.2, 1.1, 0.0]]
      events:
        - {name: cart_in, at: 3.0, add: {box: [3.6, 0.1, 4.2, 2.1], name: cart}}
        - {name: cart_out, at: 11.0, remove: cart}
      time_limit: 60
      expect:
        outcome: succeeded
      """)

# tight parking with a small yaw tolerance
g = G(70, 40, ) if False else G(70, 40)
g.fill(40, 1, 40, 8, "#"); g.fill(48, 1, 48, 8, "#")            # bay x 4.1..4.8 (0.7 m), 0.8 deep
write("parking_bay_small_yaw",
      "Park in a bay 0.7 m wide (the robot is 0.44 m wide), facing into it, within 10 cm and 0.1 "
      "rad. A good tree lines up in front of the bay first and drives straight in slowly.", g, """
      start: [1.0, 2.5, 0.0]
      goals: [[4.45, 0.55, -1.5708]]
      params:
        DWAPlannerROS: {xy_goal_tolerance: 0.1, yaw_goal_tolerance: 0.1}
        global_costmap: {inflation_layer: {inflation_radius: 0.3}}
        local_costmap: {inflation_layer: {inflation_radius: 0.3}}
      time_limit: 90
      expect:
        outcome: succeeded
        final_pose: {within: 0.1, yaw: 0.1}
        recoveries: {at_most: 3}
      """)

g = G(70, 40)
g.fill(1, 20, 8, 20, "#"); g.fill(1, 28, 8, 28, "#")              # side bay y 2.1..2.8 at the west wall
write("parking_side_bay",
      "Park in a side bay 0.7 m wide and 0.8 m deep at the west wall, facing west, within 10 cm and "
      "0.15 rad.", g, """
      start: [5.0, 1.0, 3.1416]
      goals: [[0.55, 2.45, 3.1416]]
      params:
        DWAPlannerROS: {xy_goal_tolerance: 0.1, yaw_goal_tolerance: 0.15}
        global_costmap: {inflation_layer: {inflation_radius: 0.3}}
        local_costmap: {inflation_layer: {inflation_radius: 0.3}}
      time_limit: 90
      expect:
        outcome: succeeded
        final_pose: {within: 0.1, yaw: 0.15}
        recoveries: {at_most: 3}
      """)

# starts inside inflated space
g = G(60, 30)
write("start_in_inflation_wall",
      "The robot starts 10 cm from a wall, inside the inflated space. It must get out by the "
      "straightest free move and reach the goal, without touching the wall.", g, """
      start: [3.0, 0.45, 0.0]
      goals: [[3.0, 2.2, 1.5708]]
      time_limit: 40
      expect:
        outcome: succeeded
        max_time: 30
      """)

write("start_in_inflation_global_planner",
      "The same start inside inflated space with global_planner, which reports START_OCCUPIED "
      "where navfn plans from it silently: the tree must escape and still get there.", g, """
      start: [3.0, 0.45, 0.0]
      goals: [[3.0, 2.2, 1.5708]]
      params:
        move_base: {base_global_planner: global_planner/GlobalPlanner}
      time_limit: 40
      expect:
        outcome: succeeded
        max_time: 30
      """)

g = G(60, 30)
g.fill(28, 1, 29, 28, "#"); g.fill(28, 10, 29, 18, ".")           # door y 1.0..1.9 in a wall x 2.8
write("start_in_doorway_corner",
      "The robot starts right beside a door post, its inflated footprint touching the post, the "
      "goal on the far side of the room. It must free itself without a contact.", g, """
      start: [2.45, 0.75, 0.0]
      goals: [[5.0, 2.2, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
      """)

# permanently blocked routes: fail cleanly, with the right reason, soon

g = G(60, 40)
g.rect(40, 10, 50, 20, "#")
write("goal_walled_in",
      "The goal lies in a closed room the map shows (no door). Planning fails at once: the tree "
      "must end with NO_VALID_PATH quickly and not wander about trying.", g, """
      start: [1.0, 1.0, 0.0]
      goals: [[4.5, 1.5, 0.0]]
      time_limit: 60
      expect:
        outcome: failed
        reason: NO_VALID_PATH
        max_time: 20
        recoveries: {at_most: 6}
      """)

g = G(70, 24)
g.fill(35, 1, 36, 22, "#"); g.fill(35, 9, 36, 14, ".")           # a door 0.6 m
write("door_closed_ahead",
      "A door is closed (a panel appears in it) while the robot drives to it; there is no other "
      "way. The tree must stop trying and end with NO_VALID_PATH within 60 s.", g, """
      start: [1.0, 1.2, 0.0]
      goals: [[6.0, 1.2, 0.0]]
      events:
        - {name: closed, at: 1.0, add: {box: [3.45, 0.85, 3.75, 1.55], name: door_panel}}
      time_limit: 90
      expect:
        outcome: failed
        reason: NO_VALID_PATH
        max_time: 60
      """)


# oscillation at junctions
g = G(70, 40)
g.fill(35, 1, 36, 38, "#"); g.fill(35, 10, 36, 17, "."); g.fill(35, 22, 36, 29, ".")
g.fill(40, 17, 55, 22, "#")
write("junction_two_gaps",
      "Two equal gaps in a wall, the goal straight ahead behind a block between them. A robot that "
      "dithers between the gaps must notice and commit to one: it gets there within 40 s.", g, """
      start: [1.0, 2.0, 0.0]
      goals: [[6.2, 2.0, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
        max_time: 40
        recoveries: {at_most: 4}
      """)

g = G(70, 40)
g.fill(35, 1, 36, 38, "#"); g.fill(35, 14, 36, 25, ".")
g.fill(50, 14, 51, 25, "#")
write("junction_blocked_branch",
      "Past a wide door a wall stands across the straight line; left or right are both fine. The "
      "robot must choose and go, not swing between the two.", g, """
      start: [1.0, 2.0, 0.0]
      goals: [[6.2, 2.0, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
        max_time: 35
      """)

# route, speed and reverse expectations
g = G(70, 30)
write("speed_limit_zone",
      "A speed limit is set for the second half of the hall (a parameter change at 1 s brings "
      "max_vel_x down to 0.2 m/s). The robot must keep below 0.25 m/s there.", g, """
      start: [0.8, 1.5, 0.0]
      goals: [[6.2, 1.5, 0.0]]
      events:
        - {name: slow, at: 1.0, set: {DWAPlannerROS: {max_vel_x: 0.2, max_vel_trans: 0.2}}}
      time_limit: 60
      expect:
        outcome: succeeded
        slow_in: [{box: [3.5, 0.1, 6.9, 2.9], max_speed: 0.25, name: slow_zone}]
      """)

g = G(60, 40)
write("turn_around_not_reverse",
      "The goal is 3 m behind the robot. It must turn round and drive forwards (as move_base "
      "does), not reverse along the path: no reversing for more than 1 s at a time.", g, """
      start: [4.5, 2.0, 0.0]
      goals: [[1.5, 2.0, 3.1416]]
      time_limit: 40
      expect:
        outcome: succeeded
        reverse: {max_duration: 1.0}
        max_time: 30
      """)

g = G(70, 24)
g.fill(30, 1, 31, 22, "#"); g.fill(30, 7, 31, 16, "P")
write("phantom_moves_away",
      "A phantom blocks the doorway; 3 s in it moves off to the side (as a stale reading is "
      "replaced by a fresh one). The robot goes through the doorway.", g, """
      start: [4.5, 1.2, 3.1416]
      goals: [[1.2, 1.2, 3.1416]]
      phantoms:
        - {box: [2.9, 0.6, 3.3, 1.7], costmap: both, name: ghost}
      events:
        - {name: ghost_moves, at: 3.0, move_phantom: ghost, to: {box: [4.0, 1.9, 4.3, 2.2]}}
      time_limit: 60
      expect:
        outcome: succeeded
        via: [{box: [2.9, 0.6, 3.3, 1.7], name: doorway}]
      """)

g = G(70, 30)
g.fill(30, 1, 40, 14, "?")
write("unknown_area_solid",
      "A part of the map is unknown and, in the world, solid (unknown: solid). The costmaps treat "
      "unknown as free, so the straight plan crosses it; the laser shows the truth. The robot must "
      "go round without a contact.", g, """
      start: [1.0, 0.8, 0.0]
      goals: [[6.0, 0.8, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
      """, unknown="solid")

# goal inside an obstacle the map does not know (issue 17, class 7)
g = G(70, 34)
write("goal_on_unseen_pallet",
      "The goal lies just inside the edge of a pallet the map does not know (a drop-off point "
      "that something now covers). Once the laser shows the pallet, the goal cell is lethal: the "
      "robot must stop at the nearest free pose it can reach within 0.5 m of the goal (the "
      "planners' default_tolerance idea; a tree reports the substitute on its blackboard), not "
      "circle the pallet until the time limit or fail.", g, """
      start: [0.8, 1.7, 0.0]
      goals: [[4.1, 1.6, 0.0]]
      objects:
        - {box: [4.0, 1.0, 4.8, 2.3], name: pallet}
      time_limit: 60
      expect:
        outcome: succeeded
        final_pose: {of: [4.1, 1.6, 0.0], within: 0.75}   # the 0.5 m search + 0.25 m goal tolerance
        max_time: 30
      """)

# dithering between two gaps (issue 17, class 4): two 0.7 m gaps either side of a block, the
# robot a little off the middle; each replan picks the other gap while the local planner slides
# along the wall in front of the one it was heading for
g = G(70, 40)
g.fill(35, 1, 36, 38, "#")
g.fill(35, 10, 36, 16, "."); g.fill(35, 23, 36, 29, ".")   # gaps y 1.0..1.7 and 2.3..3.0
g.fill(40, 17, 55, 22, "#")                                 # the block behind the wall
write("junction_dithering",
      "Two 0.7 m gaps in a wall either side of a block, the goal behind the block, the robot "
      "starting a little below the middle. Left alone the robot swings between the gaps: each "
      "replan picks the other one while the local planner slides along the wall in front of "
      "the gap it was heading for, until the time runs out. A good tree notices that it keeps "
      "moving without getting nearer, commits to the gap its plan takes (lines up in front of "
      "it and drives straight through) and arrives.", g, """
      start: [1.0, 1.9, 0.0]
      goals: [[6.2, 2.0, 0.0]]
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
        max_time: 45
      """)

# tight spots (issue 17, class 6)
def rotated_box(g, res, cx, cy, angle, along, across):
    """Fill the cells whose centre lies in the box [along] x [across] (m) of the frame at
    (cx, cy) turned by ``angle``: walls at any angle, drawn as the grid draws them."""
    import math
    c, s = math.cos(angle), math.sin(angle)
    for x in range(g.w):
        for y in range(g.h):
            dx, dy = (x + 0.5) * res - cx, (y + 0.5) * res - cy
            u, v = c * dx + s * dy, -s * dx + c * dy
            if along[0] <= u <= along[1] and across[0] <= v <= across[1]:
                g.set(x, y, "#")

g = G(100, 60)                                    # 5 m x 3 m at 5 cm a character
for across in ((0.38, 0.5), (-0.5, -0.38)):       # side walls 0.76 m apart (0.70 m clear on
    rotated_box(g, 0.05, 3.3, 1.3, 0.7854, (0.0, 1.02), across)   # the grid's staircase)
rotated_box(g, 0.05, 3.3, 1.3, 0.7854, (0.9, 1.02), (-0.5, 0.5))  # the bay's end
write("parking_bay_diagonal",
      "Park in a bay at 45 degrees to every wall (0.7 m clear on the grid for a 0.44 m wide "
      "body, 0.9 m deep, its mouth facing south-west), facing into it, within 10 cm and 0.1 "
      "rad. Lining up in front of it means lining up on a diagonal, on no axis of the grid.", g, """
      start: [0.8, 2.3, 0.0]
      goals: [[3.618, 1.618, 0.7854]]
      params:
        DWAPlannerROS: {xy_goal_tolerance: 0.1, yaw_goal_tolerance: 0.1}
        global_costmap: {inflation_layer: {inflation_radius: 0.3}}
        local_costmap: {inflation_layer: {inflation_radius: 0.3}}
      time_limit: 90
      expect:
        outcome: succeeded
        no_collision: true
        final_pose: {within: 0.1, yaw: 0.1}
        recoveries: {at_most: 3}
      """, resolution=0.05)

g = G(100, 60)                                    # 5 m x 3 m at 5 cm a character
g.fill(30, 1, 69, 9, "#")                         # a low shelf along the south wall, to y 0.5
write("start_beside_shelf_global_planner",
      "The robot starts parallel to a shelf, 2.5 cm from it: with global_planner its own cell is "
      "inscribed cost and the planner reports START_OCCUPIED (navfn would plan from it). Every "
      "arc swings a corner towards the shelf; driving straight along it to its end frees the "
      "robot. The goal is across the room.", g, """
      start: [2.6, 0.745, 0.0]
      goals: [[0.8, 2.4, 3.1416]]
      params:
        move_base: {base_global_planner: global_planner/GlobalPlanner}
      time_limit: 60
      expect:
        outcome: succeeded
        no_collision: true
        max_time: 40
      """, resolution=0.05)

# a fresh obstacle that leaves a long detour (issue 17, class 1, the age side): a wall with a
# near doorway that a real cabinet fills, in view from the start, and a far one at the top
g = G(80, 60)
g.fill(40, 1, 41, 58, "#")
g.fill(40, 5, 41, 15, ".")                                        # near doorway y 0.5..1.6
g.fill(40, 50, 41, 58, ".")                                       # far doorway y 5.0..5.9
write("doorway_blocked_in_view",
      "A cabinet the map does not know fills the near doorway, and the robot faces it from the "
      "start: the laser sees it all along. The only way is the far doorway, a detour more than "
      "twice as long. A good tree tells this obstacle, seen a moment ago, from a stale one (the "
      "blocking cells' age) and drives the detour without clearing what its laser is looking "
      "at.", g, """
      start: [2.0, 1.0, 0.0]
      goals: [[6.0, 1.0, 0.0]]
      objects:
        - {box: [3.9, 0.4, 4.3, 1.7], name: cabinet}
      time_limit: 90
      expect:
        outcome: succeeded
        via: [{box: [3.9, 5.0, 4.3, 5.9], name: far_doorway}]
        recoveries: {none_of: [ClearGlobalBeforeDetour]}
        max_time: 45
      """)

g = G(70, 40)
g.fill(29, 31, 29, 38, "#"); g.fill(37, 31, 37, 38, "#")   # bay x 3.0..3.7 (0.7 m), 0.8 m deep
write("park_and_leave_bay",
      "Park facing into a bay 0.7 m wide at the north wall (within 10 cm and 0.1 rad), then leave "
      "it for a goal back across the room. Getting out means backing straight out the way it "
      "came in, through space the laser, facing the bay's end, does not see.", g, """
      start: [1.0, 1.0, 0.0]
      goals: [[3.35, 3.45, 1.5708], [1.0, 1.0, 3.1416]]
      params:
        DWAPlannerROS: {xy_goal_tolerance: 0.1, yaw_goal_tolerance: 0.1}
        global_costmap: {inflation_layer: {inflation_radius: 0.3}}
        local_costmap: {inflation_layer: {inflation_radius: 0.3}}
      time_limit: 90
      expect:
        outcome: succeeded
        no_collision: true
        goals_reached: 2
        recoveries: {at_most: 3}
      """)

# blind reverse (issue 17, class 5): a local planner allowed to reverse, a box in the blind sector
g = G(60, 40)
write("reversing_planner_box_behind",
      "The goal is 3 m behind the robot and its local planner may drive backwards (DWAPlannerROS "
      "min_vel_x -0.3, as some robots are configured). A box the map does not know stands on the "
      "straight way back, in the 240-degree laser's blind sector: following the path backwards "
      "drives into it unseen. The robot must turn round first, as move_base's planner with "
      "min_vel_x 0 does (then it sees the box and goes round): no reversing for more than 1 s "
      "at a time, no contact.", g, """
      start: [4.5, 2.0, 0.0]
      goals: [[1.2, 2.0, 3.1416]]
      objects:
        - {box: [2.6, 1.6, 2.9, 2.4], name: box}
      params:
        DWAPlannerROS: {min_vel_x: -0.3}
      time_limit: 40
      expect:
        outcome: succeeded
        no_collision: true
        reverse: {max_duration: 1.0}
        max_time: 30
      """)
