"""YAML / XML tree loading: validation messages, namespaces, subtrees, includes, export."""

from __future__ import annotations

import textwrap
import xml.etree.ElementTree as ET

import pytest
from py_trees.common import Status

from behaviors.testing import ScriptedWorld, run_tree
from executive.tree_loader import (SHIPPED_TREES, TreeLoadError, load_tree_file,
                                   shipped_tree, to_xml)
from navcore.types import Pose2D


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text).lstrip("\n"))
    return p


def error_of(tmp_path, text, name="t.yaml"):
    p = write(tmp_path, name, text)
    with pytest.raises(TreeLoadError) as e:
        load_tree_file(p, "/err")
    return str(e.value).replace(str(tmp_path) + "/", "")


@pytest.mark.parametrize("name", SHIPPED_TREES)
def test_shipped_trees_load_and_export(name, tmp_path):
    loaded = load_tree_file(shipped_tree(name), namespace=f"/{name}")
    assert loaded.root.status == Status.INVALID and len(loaded.nodes()) > 10
    xml = to_xml(loaded)
    root = ET.fromstring(xml)
    assert root.attrib["BTCPP_format"] == "4"
    assert root.find("TreeNodesModel") is not None
    p = tmp_path / f"{name}.xml"
    p.write_text(xml)
    again = load_tree_file(p, namespace=f"/{name}_xml")
    assert [type(n).__name__ for n in again.nodes()] == [type(n).__name__ for n in loaded.nodes()]
    assert to_xml(again) == xml                          # the round trip is exact


def test_two_missions_do_not_share_keys():
    a = load_tree_file(shipped_tree("nav2"), namespace="/mission_a")
    b = load_tree_file(shipped_tree("nav2"), namespace="/mission_b")
    wa, wb = ScriptedWorld(), ScriptedWorld()
    a.setup(**wa.components())
    b.setup(**wb.components())
    a.set("goal", Pose2D(2.0, 0.0, 0.0))
    assert b.get("goal") is None
    b.tick()
    assert b.status == Status.RUNNING or b.status == Status.FAILURE
    assert wb.planner.calls == 0                      # mission b has no goal: nothing planned
    status, _ = run_tree(a, wa)
    assert status == Status.SUCCESS and b.get("path") is None
    for tree, ns in ((a, "/mission_a"), (b, "/mission_b")):
        for node in tree.nodes():
            for client in node.blackboards:
                for key in client.remappings.values():
                    assert key.startswith(ns + "/"), (node.name, key)


def test_unknown_node_type_suggests(tmp_path):
    msg = error_of(tmp_path, """
        main_tree: T
        trees:
          T:
            Sequence:
              children:
                - ComputePathToPos: {goal: "{goal}"}
        """)
    assert msg == "t.yaml:6: ComputePathToPos: unknown node type (did you mean 'ComputePathToPose'?)"


def test_unknown_port_suggests(tmp_path):
    msg = error_of(tmp_path, """
        trees:
          T:
            RateController:
              hzz: 2.0
              child:
                Wait: {}
        """)
    assert msg == "t.yaml:4: RateController: unknown port 'hzz' (did you mean 'hz'?)"


@pytest.mark.parametrize("body,expected", [
    ("Wait: {wait_duration: fast}", "t.yaml:3: Wait: port 'wait_duration' expects a number, got 'fast'"),
    ("RoundRobin: {wrap_around: 1, children: [Wait]}", "port 'wrap_around' expects true or false"),
    ("Timeout: {child: Wait}", "t.yaml:3: Timeout: missing required port 'msec'"),
    ("ComputePathToPose: {path: out}", "output port 'path' needs a blackboard reference"),
    ("ComputePathToPose: {goal: \"{goal\"}", "port 'goal': malformed blackboard reference '{goal'"),
    ("ComputePathToPose: {goal: \"{my goal}\"}", "malformed blackboard reference"),
    ("ClearEntireCostmap: {costmap: locl}", "port 'costmap' must be one of local, global, both, got 'locl' (did you mean 'local'?)"),
    ("RecoveryNode: {children: [Wait, Wait, Wait]}", "t.yaml:3: RecoveryNode: needs exactly 2 children, has 3"),
    ("Inverter: {children: [Wait, Wait]}", "Inverter: a decorator needs exactly one 'child:', has 2"),
    ("Wait: {child: Wait}", "Wait: is a leaf and takes no children"),
    ("Sequence: {}", "Sequence: needs 'children:'"),
    ("SubTree: {id: Recoverys}", "SubTree: unknown subtree id 'Recoverys' (did you mean 'Recoveries'?)"),
])
def test_port_and_structure_errors(tmp_path, body, expected):
    msg = error_of(tmp_path, f"""
        trees:
          T:
            {body}
          Recoveries:
            Wait: {{}}
        main_tree: T
        """)
    assert expected in msg
    assert msg.startswith("t.yaml:")


def test_error_lines_point_at_the_port(tmp_path):
    msg = error_of(tmp_path, """
        trees:
          T:
            Sequence:
              children:
                - Wait: {}
                - Spin:
                    spin_dist: 1.0
                    time_alowance: 3.0
        """)
    assert msg == "t.yaml:8: Spin: unknown port 'time_alowance' (did you mean 'time_allowance'?)"


def test_recursive_subtree_and_include_cycle(tmp_path):
    msg = error_of(tmp_path, """
        main_tree: A
        trees:
          A:
            Sequence:
              children:
                - SubTree: {id: B}
          B:
            Fallback:
              children:
                - SubTree: {id: A}
        """)
    assert "SubTree: recursive subtree: A -> B -> A" in msg and msg.startswith("t.yaml:10:")
    write(tmp_path, "b.yaml", "include: a.yaml\ntrees:\n  B:\n    Wait: {}\n")
    msg = error_of(tmp_path, "include: b.yaml\ntrees:\n  A:\n    Wait: {}\n", name="a.yaml")
    assert "include cycle: a.yaml -> b.yaml -> a.yaml" in msg


def test_yaml_syntax_and_top_level_errors(tmp_path):
    assert error_of(tmp_path, "trees:\n  T:\n    Wait: {\n").startswith("t.yaml:")
    assert "unknown top-level key 'tress' (did you mean 'trees'?)" in error_of(
        tmp_path, "tress:\n  T:\n    Wait: {}\n")
    assert "no 'main_tree'" in error_of(tmp_path, "trees:\n  A: {Wait: {}}\n  B: {Wait: {}}\n")
    assert "'x' appears twice" in error_of(tmp_path, "trees:\n  T:\n    Wait: {x: 1, x: 2}\n")
    msg = error_of(tmp_path, "trees:\n  T:\n    Wait: !!python/object:os.system {}\n")
    assert msg.startswith("t.yaml:3:")                         # no object construction


def test_subtree_remapping_isolation_and_literals(tmp_path):
    p = write(tmp_path, "s.yaml", """
        main_tree: Main
        trees:
          Main:
            Sequence:
              children:
                - SubTree: {id: Plan, name: isolated}
                - SubTree: {id: Plan, name: remapped, target: "{goal}", out: "{path}"}
                - SubTree: {id: Wait1, name: literal, secs: 0.5}
                - SubTree: {id: Auto, _autoremap: true}
          Plan:
            ComputePathToPose: {goal: "{target}", path: "{out}"}
          Wait1:
            Wait: {wait_duration: "{secs}"}
          Auto:
            ComputePathToPose: {goal: "{goal}", path: "{auto_path}"}
        """)
    t = load_tree_file(p, "/m")
    keys = [(n.port_key("goal"), n.port_key("path")) for n in t.nodes()
            if type(n).__name__ == "ComputePathToPose"]
    assert keys == [("/m/isolated/target", "/m/isolated/out"), ("/m/goal", "/m/path"),
                    ("/m/goal", "/m/auto_path")]
    wait = next(n for n in t.nodes() if type(n).__name__ == "Wait")
    assert wait.get_input("wait_duration") == 0.5
    msg = error_of(tmp_path, """
        main_tree: M
        trees:
          M:
            SubTree: {id: P, gaol: "{goal}"}
          P:
            ComputePathToPose: {goal: "{goal}"}
        """)
    assert "subtree 'P' does not use key 'gaol' (did you mean 'goal'?)" in msg


def test_include_brings_in_trees(tmp_path):
    write(tmp_path, "rec.yaml", """
        trees:
          Recoveries:
            RoundRobin:
              children:
                - Spin: {spin_dist: 1.0}
                - Wait: {wait_duration: 1.0}
        """)
    p = write(tmp_path, "main.yaml", """
        include: rec.yaml
        main_tree: Main
        trees:
          Main:
            RecoveryNode:
              children:
                - NavigateToPose: {}
                - SubTree: {id: Recoveries}
        """)
    t = load_tree_file(p)
    assert [type(n).__name__ for n in t.nodes()][-4:] == ["Spin", "Wait", "RoundRobin",
                                                         "RecoveryNode"]


NAV2_JAZZY = """<?xml version="1.0"?>
<root BTCPP_format="4" main_tree_to_execute="MainTree">
  <BehaviorTree ID="MainTree">
    <RecoveryNode number_of_retries="6" name="NavigateRecovery">
      <PipelineSequence name="NavigateWithReplanning">
        <ControllerSelector selected_controller="{selected_controller}" default_controller="FollowPath" topic_name="controller_selector"/>
        <RateController hz="1.0">
          <RecoveryNode number_of_retries="1" name="ComputePathToPose">
            <ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased" error_code_id="{compute_path_error_code}"/>
            <Sequence>
              <WouldAPlannerRecoveryHelp error_code="{compute_path_error_code}"/>
              <ClearEntireCostmap name="ClearGlobalCostmap-Context" service_name="global_costmap/clear_entirely_global_costmap"/>
            </Sequence>
          </RecoveryNode>
        </RateController>
        <RecoveryNode number_of_retries="1" name="FollowPath">
          <FollowPath path="{path}" controller_id="FollowPath" error_code_id="{follow_path_error_code}"/>
          <Sequence>
            <WouldAControllerRecoveryHelp error_code="{follow_path_error_code}"/>
            <ClearEntireCostmap name="ClearLocalCostmap-Context" service_name="local_costmap/clear_entirely_local_costmap"/>
          </Sequence>
        </RecoveryNode>
      </PipelineSequence>
      <Sequence>
        <Fallback>
          <WouldAControllerRecoveryHelp error_code="{follow_path_error_code}"/>
          <WouldAPlannerRecoveryHelp error_code="{compute_path_error_code}"/>
        </Fallback>
        <ReactiveFallback name="RecoveryFallback">
          <GoalUpdated/>
          <RoundRobin name="RecoveryActions">
            <Sequence name="ClearingActions">
              <ClearEntireCostmap name="ClearLocalCostmap-Subtree" service_name="local_costmap/clear_entirely_local_costmap"/>
              <ClearEntireCostmap name="ClearGlobalCostmap-Subtree" service_name="global_costmap/clear_entirely_global_costmap"/>
            </Sequence>
            <Spin spin_dist="1.57" error_code_id="{spin_error_code}"/>
            <Wait wait_duration="5.0"/>
            <BackUp backup_dist="0.30" backup_speed="0.15" error_code_id="{backup_error_code}"/>
          </RoundRobin>
        </ReactiveFallback>
      </Sequence>
    </RecoveryNode>
  </BehaviorTree>
</root>
"""


def test_nav2_xml_loads_and_unsupported_nodes_are_named(tmp_path):
    p = write(tmp_path, "nav2.xml", NAV2_JAZZY.replace(
        '<Sequence>\n              <WouldAPlannerRecoveryHelp',
        '<Sequence>\n              <AssistedTeleop/>\n              <WouldAPlannerRecoveryHelp'))
    with pytest.raises(TreeLoadError) as e:
        load_tree_file(p)
    assert ("nav2.xml:11: AssistedTeleop: a Nav2 node (humble, jazzy, kilted, main) that navbt "
            "does not provide: needs a teleoperation input") in str(e.value)
    p2 = write(tmp_path, "nav2b.xml", NAV2_JAZZY)
    t = load_tree_file(p2, namespace="/x")
    clears = [n for n in t.nodes() if type(n).__name__ == "ClearEntireCostmap"]
    assert [c.get_input("costmap") for c in clears] == ["global", "local", "local", "global"]
    w = ScriptedWorld()
    t.setup(**w.components())
    t.set("goal", Pose2D(1.0, 1.0, 0.0))
    status, _ = run_tree(t, w)
    assert status == Status.SUCCESS


def test_xml_errors_have_lines(tmp_path):
    p = write(tmp_path, "bad.xml", """
        <root BTCPP_format="4" main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <Sequence>
              <Wait wait_duration="soon"/>
            </Sequence>
          </BehaviorTree>
        </root>
        """)
    with pytest.raises(TreeLoadError, match=r"bad.xml:4: Wait: port 'wait_duration' expects"):
        load_tree_file(p)
    p = write(tmp_path, "broken.xml", "<root>\n  <BehaviorTree ID='T'>\n</root>\n")
    with pytest.raises(TreeLoadError, match=r"broken.xml:3: not valid XML"):
        load_tree_file(p)


def test_py_trees_own_xml_parser_builds_our_nodes(tmp_path):
    """Our classes are py_trees ports classes: py_trees' BT.CPP parser instantiates them too."""
    from py_trees.parsers.behaviour_tree_xml import parse_behaviour_tree_xml
    p = write(tmp_path, "pt.xml", """
        <root main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <RecoveryNode name="rn" number_of_retries="2">
              <Wait name="w1" wait_duration="0.1"/>
              <ClearEntireCostmap name="c" costmap="local"/>
            </RecoveryNode>
          </BehaviorTree>
        </root>
        """)
    root = parse_behaviour_tree_xml(str(p))
    assert type(root).__name__ == "RecoveryNode"
    assert [type(c).__name__ for c in root.children] == ["Wait", "ClearEntireCostmap"]
    assert root.get_input("number_of_retries") == 2


def test_namespace_must_be_absolute():
    with pytest.raises(TreeLoadError, match="namespace must be an absolute name"):
        load_tree_file(shipped_tree("nav2"), namespace="mission")


@pytest.mark.parametrize("name", SHIPPED_TREES)
def test_yaml_export_round_trip(name, tmp_path):
    from executive.tree_loader import to_yaml
    loaded = load_tree_file(shipped_tree(name), namespace="/y1")
    text = to_yaml(loaded)
    p = tmp_path / "again.yaml"
    p.write_text(text)
    again = load_tree_file(p, namespace="/y2")
    assert to_yaml(again) == text
    assert to_xml(again) == to_xml(loaded)


def test_xml_to_yaml_types_the_literals(tmp_path):
    from executive.tree_loader import to_yaml
    p = write(tmp_path, "nav2b.xml", NAV2_JAZZY)
    text = to_yaml(load_tree_file(p))
    assert "wait_duration: 5.0" in text and "number_of_retries: 6" in text
    # Nav2's attributes stay as written (issue 19) and still pick the costmap
    assert "service_name: local_costmap/clear_entirely_local_costmap" in text
    assert "costmap:" not in text
    y = tmp_path / "nav2b.yaml"
    y.write_text(text)
    t = load_tree_file(y)
    spin = next(n for n in t.nodes() if type(n).__name__ == "Spin")
    assert spin.get_input("spin_dist") == 1.57
    clears = [n for n in t.nodes() if type(n).__name__ == "ClearEntireCostmap"]
    assert [c.get_input("costmap") for c in clears] == ["global", "local", "local", "global"]


def test_docs_node_reference_is_in_step():
    """docs/trees.md carries the generated node table; regenerate it when ports change."""
    from pathlib import Path

    from behaviors.registry import markdown_catalogue
    text = (Path(__file__).resolve().parent.parent / "docs" / "trees.md").read_text()
    start, end = "<!-- nodes:start -->\n", "<!-- nodes:end -->"
    table = text[text.index(start) + len(start):text.index(end)]
    assert table == markdown_catalogue(), "run: python -m behaviors.registry"


def test_a_read_key_nothing_writes_is_caught_when_it_is_a_typo(tmp_path):
    msg = error_of(tmp_path, """
        trees:
          T:
            PipelineSequence:
              children:
                - ComputePathToPose: {goal: "{goal}", path: "{plan}"}
                - FollowPath: {path: "{plna}"}
        """)
    assert msg == ("t.yaml:6: FollowPath: port 'path' reads '{plna}', which nothing in the tree "
                   "writes (did you mean 'plan'?)")
    msg = error_of(tmp_path, """
        trees:
          T:
            GoalReached: {goal: "{gaol}"}
        """)
    assert "reads '{gaol}', which nothing in the tree writes (did you mean 'goal'?)" in msg
    p = write(tmp_path, "ok.yaml", """
        trees:
          T:
            Wait: {wait_duration: "{operator_pause}"}
        """)
    load_tree_file(p)                                   # an unrelated external key is fine


def test_xml_include_and_subtree_remapping(tmp_path):
    write(tmp_path, "rec.xml", """
        <root BTCPP_format="4">
          <BehaviorTree ID="Plan">
            <ComputePathToPose goal="{target}" path="{out}"/>
          </BehaviorTree>
        </root>
        """)
    p = write(tmp_path, "main.xml", """
        <root BTCPP_format="4" main_tree_to_execute="Main">
          <include path="rec.xml"/>
          <BehaviorTree ID="Main">
            <Sequence>
              <SubTree ID="Plan" name="p" target="{goal}" out="{path}"/>
              <FollowPath path="{path}"/>
            </Sequence>
          </BehaviorTree>
        </root>
        """)
    t = load_tree_file(p, namespace="/xi")
    plan = next(n for n in t.nodes() if type(n).__name__ == "ComputePathToPose")
    assert (plan.port_key("goal"), plan.port_key("path")) == ("/xi/goal", "/xi/path")
    w = ScriptedWorld()
    t.setup(**w.components())
    t.set("goal", Pose2D(1.0, 0.0, 0.0))
    status, _ = run_tree(t, w)
    assert status == Status.SUCCESS


def test_tree_error_knows_file_line_and_excerpt(tmp_path):
    p = write(tmp_path, "t.yaml", "trees:\n  T:\n    Spin: {spin_dits: 1.0}\n")
    with pytest.raises(TreeLoadError) as e:
        load_tree_file(p)
    assert e.value.file == str(p) and e.value.line == 3
    assert e.value.excerpt() == "    Spin: {spin_dits: 1.0}"


def test_tagged_sequences_and_scalars_are_refused(tmp_path):
    msg = error_of(tmp_path, "trees:\n  T:\n    Sequence:\n      children: !!python/tuple [Wait]\n")
    assert "YAML tag 'tag:yaml.org,2002:python/tuple' is not allowed" in msg
    msg = error_of(tmp_path, "trees:\n  T:\n    Wait: {wait_duration: !!python/name:os.getcwd ''}\n")
    assert msg.startswith("t.yaml:3:")
