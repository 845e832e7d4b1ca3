"""BehaviorTree.CPP 4 built-ins (issue 19): the scripting subset (own parser, never eval),
Script/ScriptCondition/SetBlackboard/UnsetBlackboard/Sleep/WasEntryUpdated, the decorators
and controls, and the _skipIf/_while/_onSuccess... attributes, loaded from YAML and XML."""

from __future__ import annotations

import itertools
import textwrap

import py_trees
import pytest
from py_trees.common import Status

from behaviors.base import make
from behaviors.btcpp.scripting import ScriptError, compile_script, namespace_resolver
from behaviors.testing import ScriptedWorld
from executive.tree_loader import TreeLoadError, load_tree_file, to_xml, to_yaml

S, F, R, I = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID
ST = py_trees.blackboard.Blackboard.storage
_ns = itertools.count()


class Dummy(py_trees.behaviour.Behaviour):
    def __init__(self, name: str = "d", status: Status = S) -> None:
        super().__init__(name=name)
        self.next, self.ticks = status, 0

    def update(self) -> Status:
        self.ticks += 1
        return self.next


def run(text: str, storage: dict | None = None):
    st = {} if storage is None else storage
    return compile_script(text, namespace_resolver("/s")).run(st), st


@pytest.mark.parametrize("text, value", [
    ("1 + 2 * 3", 7), ("(1 + 2) * 3", 9), ("7 / 2", 3.5), ("-2 * -3", 6), ("0x10 | 1", 17),
    ("6 & 3", 2), ("6 ^ 3", 5), ("~0", -1), ("'a' .. 'b' .. 3", "ab3"), ("3 > 2 && 2 > 1", True),
    ("!(1 == 1) || false", False), ("2 >= 3 ? 'big' : 'small'", "small"), ("'5' == 5", True),
    ("NO_VALID_PATH", 208), ("FAILED_TO_MAKE_PROGRESS", 105), ("1.5e1", 15.0)])
def test_expressions(text, value):
    assert run(text)[0] == value


def test_assignments_create_and_update_entries():
    value, st = run("x := 2; x += 3; x *= 2; y := x > 5; x -= 1; x /= 3")
    assert st == {"/s/x": 3, "/s/y": True} and value == 3
    with pytest.raises(ScriptError, match="'=' on blackboard entry 'z' that does not exist"):
        run("z = 1")
    with pytest.raises(ScriptError, match="blackboard entry 'w' .* does not exist"):
        run("w + 1")
    assert run("@g := 1")[1] == {"/s/g": 1}        # mission level: the resolver's root


@pytest.mark.parametrize("text, message", [
    ("a :=", "column 5: expected a value, found the end"),
    ("3 := 4", "column 3: ':=' needs a blackboard entry on its left"),
    ("a == (1", "column 8: expected ')', found the end"),
    ("__import__('os')", "column 11: expected ';', found '('"),
    ("a; b $ c", "column 6: unexpected '$'"),
    ("", "empty script")])
def test_parse_errors_say_where(text, message):
    with pytest.raises(ScriptError, match=message.replace("(", r"\(").replace(")", r"\)")
                       .replace("$", r"\$")):
        compile_script(text, namespace_resolver("/s"))


def test_no_python_evaluation_is_reachable():
    # names are blackboard entries, calls and attributes do not parse: nothing runs Python
    for text in ("x.y", "open('f')", "[1]", "lambda: 1", "a if b else c"):
        with pytest.raises(ScriptError):
            compile_script(text, namespace_resolver("/s"))


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text).lstrip("\n"))
    return p


def loaded(tmp_path, text, name="t.yaml"):
    p = write(tmp_path, name, text)
    t = load_tree_file(p, namespace=f"/bt{next(_ns)}")
    w = ScriptedWorld()
    t.setup(**w.components())
    return t, w


def test_scripts_in_a_tree_read_and_write_the_blackboard(tmp_path):
    t, _ = loaded(tmp_path, """
        trees:
          T:
            Sequence:
              children:
                - Script: {code: "count := 0; limit := 3"}
                - RetryUntilSuccessful:
                    num_attempts: 10
                    child:
                      Sequence:
                        children:
                          - Script: {code: "count += 1"}
                          - ScriptCondition: {code: "count >= limit"}
                - SetBlackboard: {value: "{count}", output_key: "{copy}"}
                - UnsetBlackboard: {key: limit}
        """)
    for _ in range(10):
        t.tick()
        if t.status is not R:
            break
    assert t.status == S
    assert t.get("count") == 3 and t.get("copy") == 3 and t.get("limit") is None


def test_script_errors_are_load_errors_with_file_and_line(tmp_path):
    p = write(tmp_path, "t.yaml", """
        trees:
          T:
            Sequence:
              children:
                - Script: {code: "x := (1 + 2"}
                - Wait: {wait_duration: 1.0, _skipIf: "x >"}
        """)
    with pytest.raises(TreeLoadError) as e:
        load_tree_file(p)
    lines = str(e.value).splitlines()
    assert lines[0].endswith("t.yaml:5: Script: code: column 12: expected ')', found the end")
    assert lines[1].endswith("t.yaml:6: Wait: _skipIf: column 4: expected a value, found the "
                             "end")


def test_pre_and_post_conditions(tmp_path):
    t, w = loaded(tmp_path, """
        <root BTCPP_format="4" main_tree_to_execute="T">
          <BehaviorTree ID="T">
            <Sequence>
              <Script code="n := 0; done := false; halted := 0"/>
              <Wait wait_duration="5.0" _skipIf="n == 0" _onSuccess="done := true"/>
              <Wait name="W2" wait_duration="0.1" _failureIf="n > 5" _post="n += 10"/>
              <Fallback>
                <AlwaysSuccess _skipIf="true"/>
                <Script code="fallback_went_on := true"/>
              </Fallback>
            </Sequence>
          </BehaviorTree>
        </root>""", "t.xml")
    t.tick()                               # first Wait skipped (n == 0): W2 starts
    assert t.status == R and t.get("done") is False
    w.clock.advance(0.1)
    t.tick()
    assert t.status == S and t.get("n") == 10 and t.get("fallback_went_on") is True
    xml = to_xml(t)
    assert '_skipIf="n == 0"' in xml and '_onSuccess="done := true"' in xml
    assert "_post: n += 10" in to_yaml(t)


def test_while_halts_a_running_node(tmp_path):
    t, w = loaded(tmp_path, """
        trees:
          T:
            Sequence:
              children:
                - Script: {code: "go := true"}
                - Wait: {wait_duration: 10.0, _while: "go", _onHalted: "stopped := 1"}
                - Script: {code: "after := 1"}
        """)
    t.tick()
    assert t.status == R
    t.set("go", False)
    t.tick()
    assert t.status == S and t.get("stopped") == 1 and t.get("after") == 1


def node(node_type, **kw):
    n = make(node_type, namespace=f"/bn{next(_ns)}", **kw)
    w = ScriptedWorld()
    for m in n.iterate():
        if hasattr(m, "setup"):
            m.setup(**w.components())
    return n, w


def ticks(n, k):
    out = []
    for _ in range(k):
        n.tick_once()
        out.append(n.status)
    return out


def test_async_sequence_and_fallback_yield_between_children():
    a, b = Dummy("a"), Dummy("b")
    seq, _ = node("AsyncSequence", children=[a, b])
    assert ticks(seq, 2) == [R, S] and (a.ticks, b.ticks) == (1, 1)
    a, b = Dummy("a", F), Dummy("b", F)
    fb, _ = node("AsyncFallback", children=[a, b])
    assert ticks(fb, 2) == [R, F]


def test_parallel_all_counts_failures():
    a, b, c = Dummy("a", S), Dummy("b", R), Dummy("c", F)
    p, _ = node("ParallelAll", children=[a, b, c], max_failures=2)
    assert ticks(p, 1) == [R]
    b.next = F
    assert ticks(p, 1) == [F] and a.ticks == 1          # finished children not re-ticked
    a, b, c = Dummy("a", S), Dummy("b", S), Dummy("c", F)
    p, _ = node("ParallelAll", children=[a, b, c], max_failures=2)
    assert ticks(p, 1) == [S]


def test_while_do_else_is_reactive():
    cond, do, other = Dummy("c", S), Dummy("do", R), Dummy("else", R)
    n, _ = node("WhileDoElse", children=[cond, do, other])
    assert ticks(n, 1) == [R] and do.status == R
    cond.next = F
    assert ticks(n, 1) == [R] and do.status == I and other.status == R
    other.next = S
    assert ticks(n, 1) == [S]


def test_try_catch_runs_the_catch_and_fails():
    a, b, catch = Dummy("a", S), Dummy("b", F), Dummy("catch", R)
    n, _ = node("TryCatch", children=[a, b, catch])
    assert ticks(n, 1) == [R] and catch.ticks == 1
    catch.next = S
    assert ticks(n, 1) == [F] and catch.ticks == 2
    b.next = S
    assert ticks(n, 1) == [S]


def test_switch_picks_the_matching_case_or_the_default():
    kids = [Dummy("one"), Dummy("two"), Dummy("default")]
    n, _ = node("Switch2", children=kids, variable="{mode}", case_1="1", case_2="fast")
    ST[f"{n.namespace}/mode"] = "fast"
    ticks(n, 1)
    ST[f"{n.namespace}/mode"] = 1
    ticks(n, 1)
    ST[f"{n.namespace}/mode"] = "other"
    ticks(n, 1)
    assert [k.ticks for k in kids] == [1, 1, 1]


def test_loops_pop_values():
    child = Dummy()
    n, _ = node("LoopInt", child=child, queue="1;2;3", value="{v}")
    seen = []
    for _ in range(4):
        n.tick_once()
        seen.append((n.status, ST.get(f"{n.namespace}/v")))
    assert seen == [(R, 1), (R, 2), (R, 3), (S, 3)]
    n, _ = node("LoopString", child=Dummy(status=F), queue=["a", "b"], value="{v}")
    assert ticks(n, 1) == [F]


def test_precondition_run_once_sleep_and_entry_updates():
    child = Dummy(status=R)
    n, _ = node("Precondition", child=child, port_values={"if": "go == 1", "else": "SUCCESS"})
    ST[f"{n.namespace}/go"] = 0
    assert ticks(n, 1) == [S] and child.ticks == 0
    ST[f"{n.namespace}/go"] = 1
    assert ticks(n, 1) == [R]
    ST[f"{n.namespace}/go"] = 0                        # not re-checked while running
    assert ticks(n, 1) == [R] and child.ticks == 2
    child = Dummy(status=F)
    n, _ = node("RunOnce", child=child, then_skip=False)
    assert ticks(n, 3) == [F, F, F] and child.ticks == 1
    n, w = node("Sleep", msec=100)
    assert ticks(n, 1) == [R]
    w.clock.advance(0.1)
    assert ticks(n, 1) == [S]
    n, _ = node("WasEntryUpdated", entry="x")
    assert ticks(n, 1) == [F]                         # no entry yet
    ST[f"{n.namespace}/x"] = 1
    assert ticks(n, 2) == [S, F]
    ST[f"{n.namespace}/x"] = 2
    assert ticks(n, 1) == [S]
    child = Dummy()
    n, _ = node("WaitValueUpdate", child=child, entry="y")
    assert ticks(n, 1) == [R] and child.ticks == 0
    ST[f"{n.namespace}/y"] = "new"
    assert ticks(n, 1) == [S] and child.ticks == 1
