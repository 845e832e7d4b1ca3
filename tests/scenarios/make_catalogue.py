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

def write(name, description, g, body, resolution=0.1):
    art = textwrap.indent(g.text(), "    ")
    doc = f"name: {name}\ndescription: >\n{textwrap.indent(textwrap.fill(description, 96), '  ')}\n"
    doc += (f"map:\n  resolution: {resolution}\n  ascii: |\n{art}\n"
            + textwrap.dedent(body).strip() + "\n")
    with open(os.path.join(OUT, name + ".yaml"), "w") as f:
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
      expect_by_tree:
        move_base: {outcome: null}   # its four recoveries may run out first
      """)

# 2. corridor blocked for good by an object the map does not know
g = G(60, 14)
write("corridor_blocked", "A corridor blocked for good by a cabinet the map does not know. There is no "
      "way through: the robot must give up cleanly and never touch the cabinet.", g, """
      start: [0.8, 0.7, 0.0]
      goals: [[5.2, 0.7, 0.0]]
      objects:
        - {box: [3.0, 0.1, 3.3, 1.3]}
      time_limit: 60
      expect:
        outcome: failed
        no_collision: true
      expect_by_tree:
        smach_recovery: {outcome: null}   # it may still be trying when time runs out
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
        no_collision: true
      expect_by_tree:
        smach_recovery: {outcome: null}
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
      expect_by_tree:
        move_base: {outcome: null}   # gives up before its recoveries get it close enough
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
      expect_by_tree:
        move_base: {outcome: null}   # may stall at the pole; it must not touch it
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
        # no valid command, rotate_recovery blocked: move_base aborts after its recoveries
        move_base: {outcome: failed}
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
        # the local planner finds no valid command this close to the wall and rotate_recovery
        # is blocked: move_base waits out controller_patience and its four recoveries
        move_base: {outcome: timeout}
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
      "out), so neither outcome is expected; what must hold is that neither tree touches the "
      "post or the wall.", g, """
      start: [1.0, 1.0, 0.0]
      goals: [[5.0, 1.0, 0.0]]
      params:
        DWAPlannerROS: {sim_time: 3.0}
      time_limit: 60
      expect:
        # stuck at the wall post after cutting the corner on most seeds, with either tree
        outcome: null
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
      expect_by_tree:
        # with DWA's correct biases (path 32, goal 24) plain move_base drives in as well; the
        # earlier timeout here came from the 0.6 / 0.8 biases bug
        move_base: {max_time: 20}
        # within 1.5 m of the goal both weight the goal over the path and drive straight in
        smach_recovery: {max_time: 20}
        near_goal_reconfigure: {max_time: 20}
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
