"""Loading Nav2's trees (issue 19): every error at once, the right hints, attributes and
comments kept through YAML <-> XML, and the Nav2 distribution a tree follows."""

from __future__ import annotations

import textwrap

import pytest

from executive.tree_loader import TreeLoadError, load_tree_file, to_xml, to_yaml
from executive.tree_spec import TreeErrors


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text).lstrip("\n"))
    return p


BROKEN = """
<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence name="Main">
      <Wait name="Pause" wait_duration="soon"/>
      <AssistedTeleop/>
      <Spin spin_dits="1.0"/>
      <FollowPath path="{path" />
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_validate_reports_every_error_with_name_and_type(tmp_path):
    p = write(tmp_path, "bad.xml", BROKEN)
    with pytest.raises(TreeErrors) as e:
        load_tree_file(p)
    lines = [str(x) for x in e.value.errors]
    assert len(lines) == 4
    assert lines[0].endswith("bad.xml:4: Pause (Wait): port 'wait_duration' expects float, "
                             "got 'soon'")
    assert lines[1].endswith("bad.xml:5: AssistedTeleop: a Nav2 node (humble, jazzy, kilted, "
                             "main) that navbt does not provide: needs a teleoperation input "
                             "(joystick) navbt does not have")
    assert lines[2].endswith("bad.xml:6: Spin: unknown port 'spin_dits' (did you mean "
                             "'spin_dist'?)")
    assert "bad.xml:7: FollowPath: port 'path': malformed blackboard reference" in lines[3]
    assert e.value.file == str(p) and e.value.line == 4


def test_cli_validate_prints_every_error(tmp_path, capsys):
    from executive.cli import main
    p = write(tmp_path, "bad.xml", BROKEN)
    assert main(["validate", str(p)]) == 1
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 4 and all(ln.startswith(f"mission validate: {p}:") for ln in err)


def test_a_nav2_or_btcpp_node_gets_no_lookalike_suggestion(tmp_path):
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4">
          <BehaviorTree ID="T">
            <Sequence>
              <DockRobot/>
              <GoalUpdatedd/>
            </Sequence>
          </BehaviorTree>
        </root>
        """)
    with pytest.raises(TreeErrors) as e:
        load_tree_file(p)
    a, b = (str(x) for x in e.value.errors)
    assert "DockRobot: a Nav2 node (jazzy, kilted, main)" in a and "did you mean" not in a
    assert "GoalUpdatedd: unknown node type (did you mean 'GoalUpdated'?)" in b


def test_xml_messages_name_main_tree_to_execute(tmp_path):
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4" main_tree_to_execute="Missing">
          <BehaviorTree ID="T"><Wait/></BehaviorTree>
          <BehaviorTree ID="U"><Wait/></BehaviorTree>
        </root>
        """)
    with pytest.raises(TreeLoadError, match="main_tree_to_execute 'Missing' is not defined"):
        load_tree_file(p)
    p = write(tmp_path, "u.xml", """
        <root BTCPP_format="4">
          <BehaviorTree ID="T"><Wait/></BehaviorTree>
          <BehaviorTree ID="U"><Wait/></BehaviorTree>
        </root>
        """)
    with pytest.raises(TreeLoadError, match="no 'main_tree_to_execute' saying which one runs"):
        load_tree_file(p)


def test_explicit_form_loads_and_round_trips(tmp_path):
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4" main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <Control ID="Sequence" name="S">
              <Action ID="Wait" name="W" wait_duration="2.5"/>
              <Condition ID="GoalUpdated"/>
            </Control>
          </BehaviorTree>
        </root>
        """)
    t = load_tree_file(p)
    assert type(t.root).__name__ == "Sequence"
    assert [type(n).__name__ for n in t.root.children] == ["Wait", "GoalUpdated"]
    assert t.root.children[0].get_input("wait_duration") == 2.5
    xml = to_xml(t)
    assert '<Action ID="Wait" name="W" wait_duration="2.5"/>' in xml
    assert '<Control ID="Sequence" name="S">' in xml


def test_service_name_picks_the_costmap_or_is_refused(tmp_path):
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4">
          <BehaviorTree ID="T">
            <Sequence>
              <ClearEntireCostmap service_name="local_costmap/clear_entirely_local_costmap"/>
              <ClearCostmapExceptRegion service_name="global_costmap/clear_except_global_costmap"/>
              <ClearEntireCostmap name="Odd" service_name="my_costmap/clear"/>
            </Sequence>
          </BehaviorTree>
        </root>
        """)
    with pytest.raises(TreeErrors) as e:
        load_tree_file(p)
    (err,) = e.value.errors
    assert "t.xml:6: Odd (ClearEntireCostmap): service_name 'my_costmap/clear' names neither " \
           "the local nor the global costmap" in str(err)
    p.write_text(p.read_text().replace('<ClearEntireCostmap name="Odd" service_name='
                                       '"my_costmap/clear"/>', ""))
    t = load_tree_file(p)
    assert [n.get_input("costmap") for n in t.root.children] == ["local", "global"]


ROUND = """
<?xml version="1.0"?>
<!-- file comment -->
<root BTCPP_format="4" main_tree_to_execute="T">
  <BehaviorTree ID="T">
    <Sequence>
      <!-- clear the local costmap first -->
      <ClearEntireCostmap name="ClearLocal" server_timeout="150"
                          service_name="local_costmap/clear_entirely_local_costmap"/>
      <ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased"
                         server_timeout="10" error_code_id="{e}"/>
      <FollowPath path="{path}" controller_id="FollowPath" server_name="follow_path"/>
    </Sequence>
  </BehaviorTree>
</root>
"""


def test_round_trip_keeps_every_attribute_and_comment(tmp_path):
    p = write(tmp_path, "t.xml", ROUND)
    t = load_tree_file(p)
    assert any("server_timeout" in note for note in t.ignored)
    text = to_yaml(t)
    for piece in ("server_timeout: '150'",
                  "service_name: local_costmap/clear_entirely_local_costmap",
                  "server_name: follow_path", "# clear the local costmap first", "# file comment",
                  "nav2_distro: jazzy"):
        assert piece in text
    y = tmp_path / "t.yaml"
    y.write_text(text)
    again = load_tree_file(y)
    xml = to_xml(again)
    assert 'server_timeout="150"' in xml and 'server_timeout="10"' in xml
    assert "<!-- clear the local costmap first -->" in xml and "<!-- file comment -->" in xml
    assert 'nav2_distro="jazzy"' in xml
    x = tmp_path / "again.xml"
    x.write_text(xml)
    assert to_yaml(load_tree_file(x)) == text


def test_distribution_from_file_attribute_option_and_default(tmp_path):
    body = """
        <root {attrs}>
          <BehaviorTree ID="T">
            <RoundRobin><Wait/><Wait/></RoundRobin>
          </BehaviorTree>
        </root>
        """
    cases = [('BTCPP_format="4"', None, "jazzy", True),
             ('main_tree_to_execute="T"', None, "humble", True),     # BT.CPP 3: Humble
             ('BTCPP_format="4" nav2_distro="main"', None, "main", False),
             ('BTCPP_format="4" nav2_distro="main"', "kilted", "kilted", True)]
    for i, (attrs, option, distro, wraps) in enumerate(cases):
        p = write(tmp_path, f"t{i}.xml", body.format(attrs=attrs))
        t = load_tree_file(p, nav2_distro=option)
        assert t.distro == distro
        assert t.root.get_input("wrap_around") is wraps
    y = write(tmp_path, "t.yaml", "trees:\n  T:\n    RoundRobin: {children: [Wait, Wait]}\n")
    assert load_tree_file(y).distro is None                      # navbt's own semantics
    assert load_tree_file(y).root.get_input("wrap_around") is False
    assert load_tree_file(y, nav2_distro="jazzy").root.get_input("wrap_around") is True
    bad = write(tmp_path, "bad.xml", body.format(attrs='BTCPP_format="4" nav2_distro="iron"'))
    with pytest.raises(TreeLoadError, match="unknown Nav2 distribution 'iron'"):
        load_tree_file(bad)


def test_round_robin_gets_the_trees_distribution_at_build(tmp_path):
    """The builder hands the distribution to the nodes that declare they follow one (RoundRobin)
    through their constructor; other nodes get nothing. Nav2 main without wrap: a successful
    last child ends the list with FAILURE; before main (and in navbt's own) it is SUCCESS."""
    y = write(tmp_path, "t.yaml", "trees:\n  T:\n    RoundRobin:\n      wrap_around: false\n"
                                  "      children: [AlwaysSuccess, AlwaysSuccess]\n")
    expected = {None: ["SUCCESS", "SUCCESS", "FAILURE"], "jazzy": ["SUCCESS", "SUCCESS", "FAILURE"],
                "main": ["SUCCESS", "FAILURE", "SUCCESS"]}
    for distro, statuses in expected.items():
        t = load_tree_file(y, nav2_distro=distro)
        assert t.root.nav2_distro == distro
        assert not any(hasattr(c, "nav2_distro") for c in t.root.children)
        seen = []
        for _ in range(3):
            t.tick()
            seen.append(t.status.name)
        assert seen == statuses, distro


def test_mission_nodes_lists_every_nav2_node_but_the_documented_few(capsys):
    """Every node type of the four distributions' palettes and plugin registrations is a navbt
    node, except NOT_PROVIDED, and docs/trees.md names each of those with its reason."""
    from pathlib import Path

    from executive import nav2_model
    from executive.cli import main
    assert main(["nodes"]) == 0
    listed = {line.split()[0] for line in capsys.readouterr().out.splitlines()
              if line.startswith("  ")}
    missing = nav2_model.all_node_types() - listed - set(nav2_model.NOT_PROVIDED)
    assert not missing
    assert not set(nav2_model.NOT_PROVIDED) & listed
    docs = (Path(__file__).resolve().parent.parent / "docs" / "trees.md").read_text()
    for name, reason in nav2_model.NOT_PROVIDED.items():
        assert f"| `{name}` | {reason} |" in docs


def test_groot_palette_has_every_node(tmp_path, capsys):
    import xml.etree.ElementTree as ET

    from behaviors.base import node_classes
    from executive import nav2_model
    from executive.cli import main
    out = tmp_path / "palette.xml"
    assert main(["nodes", "--groot", str(out)]) == 0
    model = ET.parse(out).getroot().find("TreeNodesModel")
    ids = {el.get("ID"): el for el in model}
    expected = set(node_classes()) - set(nav2_model.BTCPP_BUILTINS)
    assert set(ids) == expected
    spin = ids["Spin"]
    assert spin.tag == "Action"
    assert {p.get("name") for p in spin} >= {"spin_dist", "time_allowance", "error_code_id",
                                            "error_msg"}
    assert ids["RecoveryNode"].tag == "Control" and ids["RateController"].tag == "Decorator"


def test_shipped_nav2_tree_exports_with_nav2_ports_only():
    """trees/nav2.yaml is written with Nav2's own ports, so its XML export passes Nav2's node
    model (every attribute of a Nav2 node type is one of that type's Nav2 ports) and loads in
    BehaviorTree.CPP with Nav2's plugins; the clear nodes still pick their costmaps."""
    import xml.etree.ElementTree as ET

    from executive import nav2_model
    from executive.tree_loader import shipped_tree
    t = load_tree_file(shipped_tree("nav2"))
    root = ET.fromstring(to_xml(t))
    for bt in root.findall("BehaviorTree"):
        for el in bt.iter():
            if nav2_model.category(el.tag) is None:
                continue
            extra = set(el.attrib) - nav2_model.any_ports(el.tag) - {"name", "ID"}
            assert not extra, (el.tag, extra)
    clears = [n for n in t.nodes() if type(n).__name__ == "ClearEntireCostmap"]
    assert sorted(c.get_input("costmap") for c in clears) == ["global", "global", "local",
                                                              "local"]


def test_mission_run_follows_the_nav2_distro_option(tmp_path, capsys):
    """mission run --nav2-distro: a one-child RoundRobin succeeds with Jazzy's rule (always
    wraps) and fails with main's (no wrap by default: the end of the list is FAILURE)."""
    from pathlib import Path

    from executive.cli import main
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4" main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <RoundRobin><Wait wait_duration="0.1"/></RoundRobin>
          </BehaviorTree>
        </root>
        """)
    office = str(Path(__file__).resolve().parent.parent / "executive/data/maps/office.yaml")
    args = ["run", str(p), "--map", office, "--start", "2,2.2,0", "--goal", "2.5,2.2",
            "--time-limit", "2.0"]
    assert main(args) == 0                                     # default: jazzy
    assert main(args + ["--nav2-distro", "main"]) == 1
    capsys.readouterr()
    with pytest.raises(SystemExit):
        main(args + ["--nav2-distro", "iron"])                 # argparse refuses it
    assert "invalid choice: 'iron'" in capsys.readouterr().err


def test_xml_structure_errors_are_reported_together(tmp_path):
    p = write(tmp_path, "t.xml", """
        <root BTCPP_format="4" main_tree_to_execute="T">
          <BehaviorTree ID="T"><Wait/></BehaviorTree>
          <BehaviorTree><Wait/></BehaviorTree>
          <BehaviorTree ID="T"><Wait/></BehaviorTree>
          <Blackboard/>
        </root>
        """)
    with pytest.raises(TreeErrors) as e:
        load_tree_file(p)
    lines = [str(x) for x in e.value.errors]
    assert lines[0].endswith("t.xml:3: <BehaviorTree> needs an ID")
    assert lines[1].endswith("t.xml:4: tree 'T' is also defined at " f"{p}:2")
    assert lines[2].endswith("t.xml:5: unexpected <Blackboard> under <root>")
