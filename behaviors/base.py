"""The three node bases of navbt (leaf, control, decorator) on py_trees ports.

Every navbt node is a ``py_trees.ports.PortsMixin`` class: ports are declared once in
``INPUT_PORTS``/``OUTPUT_PORTS`` and the class auto-registers under its name, so the YAML loader,
the BT.CPP XML loader and ``mission nodes`` all see the same catalogue.

Wiring (what the loaders do, and what tests may do by hand through ``make``):

* a port given as ``"{key}"`` reads/writes the blackboard key ``<namespace>/key``;
* a port given a literal holds that constant (kept on the node: no blackboard round trip);
* a port not given at all falls back to ``DEFAULT_KEYS`` (a well-known blackboard key such as
  ``goal`` or ``cmd_vel``) and otherwise to a private key plus the declared default value.

Every blackboard client lives under the namespace given at build time (e.g. ``/mission_3``):
py_trees storage is process-global, and this is what keeps two missions apart.
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from typing import Any, ClassVar, Iterable, Iterator

import py_trees
from py_trees.common import Status
from py_trees.ports import NoDataAvailable, PortInformation, PortsMixin, get_ports_registry
from py_trees.ports_utils import sanitize_name_for_blackboard_use

from navcore.types import Pose2D
from behaviors.errors import BehaviorError

__all__ = ["NavNode", "Leaf", "Control", "DecoratorNode", "Recovery", "PortInformation", "Port",
           "port_problem", "Status",
           "ComponentError", "make", "node_classes", "namespaced", "NoDataAvailable",
           "Ticking", "RUNNING", "SUCCESS", "FAILURE", "INVALID"]

# Status members as module constants, compared by identity: ``Status.RUNNING`` is a slow
# class-attribute look-up on an Enum and Enum ``==`` a Python-level call; ticks do many of both.
RUNNING, SUCCESS, FAILURE, INVALID = Status.RUNNING, Status.SUCCESS, Status.FAILURE, Status.INVALID

_MISSING = object()
_VETTED: set[type] = set()  # node classes whose first instance passed PortsMixin.__init__
_BB = py_trees.blackboard.Blackboard  # its class-level ``storage`` dict holds every key


@dataclass(frozen=True)
class Port(PortInformation):
    """A port whose numbers must lie in ``[low, high]`` (either bound optional).

    Every number port (``float`` or ``int``) refuses NaN, and infinity unless it is declared
    with ``finite=False`` or an infinite default (``port_problem``); ``Port`` adds the range.
    Literals are checked when the tree loads, wired values on every read.
    """

    low: float | None = None
    high: float | None = None
    finite: bool = True   # False: infinity means something (e.g. "no limit")


def port_problem(info: PortInformation, value: Any) -> str | None:
    """Why ``value`` does not fit the number port ``info`` (None when it does, or is no number);
    a pose must be finite too."""
    if isinstance(value, Pose2D):
        if not (math.isfinite(value.x) and math.isfinite(value.y) and math.isfinite(value.theta)):
            return f"must be a finite pose, got {value}"
        return None
    if info.data_type not in (float, int) or isinstance(value, bool) \
            or not isinstance(value, (int, float)):
        return None
    if isinstance(value, float) and not math.isfinite(value):
        default = info.default_value
        # infinity means something where the port says so, or is declared with it as default
        inf_allowed = not getattr(info, "finite", True) or (
            isinstance(default, float) and math.isinf(default))
        if math.isnan(value) or not inf_allowed:
            return f"must be a finite number, got {value}"
    low, high = getattr(info, "low", None), getattr(info, "high", None)
    if low is not None and value < low:
        return f"must be >= {low:g}, got {value!r}"
    if high is not None and value > high:
        return f"must be <= {high:g}, got {value!r}"
    return None


class ComponentError(BehaviorError, RuntimeError):
    """A node's ``setup`` did not receive a component it needs; the message names both."""


# What ``tick`` is: a generator of the nodes ticked, each as it finishes (py_trees' protocol).
Ticking = Iterator[py_trees.behaviour.Behaviour]


def namespaced(namespace: str, key: str) -> str:
    """Absolute blackboard key of ``key`` inside ``namespace`` (both '/'-separated)."""
    if key.startswith("/"):
        return key
    return namespace.rstrip("/") + "/" + key


class NavNode(PortsMixin):
    """Mixin of every navbt node: literal ports, well-known default keys, component lookup.

    ``DEFAULT_KEYS`` maps a port to the blackboard key it uses when the tree does not wire it
    (BT.CPP's ``"{goal}"`` default values), so a plain ``- GoalUpdated: {}`` watches ``goal``.
    """

    DEFAULT_KEYS: ClassVar[dict[str, str]] = {}
    CATEGORY: ClassVar[str] = "Action"
    # The node's place in its tree, given to ``wire`` by the tree builder: it names the node's
    # private keys (see _scoped_node_name). None: py_trees' uuid4 (nodes built by hand).
    private_tag: str | None = None
    # True for a node whose semantics changed between Nav2 distributions: the tree builder then
    # passes the tree's ``nav2_distro`` (None: navbt's own) to its constructor.
    USES_NAV2_DISTRO: ClassVar[bool] = False

    def __init__(self, name: str = "", **kwargs: Any) -> None:
        cls = type(self)
        if cls in _VETTED:
            # PortsMixin.__init__ without its abstract-class check, which scans dir() of the
            # class on every instance (a third of a tree's build); the class's first instance
            # ran it, and the class cannot change since (ABC refuses abstract classes anyway)
            class_name = kwargs.pop("behaviour_class_name", None)
            super(PortsMixin, self).__init__(name=name or cls.__name__, **kwargs)
            self._blackboard_client = None
            self._subtree_namespace = None
            self._ports_logger = None
            self._behaviour_class_name = cls.__name__ if class_name is None else class_name
        else:
            super().__init__(name=name or cls.__name__, **kwargs)
            _VETTED.add(cls)
        self._literals: dict[str, Any] = {}
        self.namespace = "/"

    # ---------------------------------------------------------------- wiring
    def wire(self, namespace: str, refs: dict[str, str] | None = None,
             literals: dict[str, Any] | None = None, private_tag: str | None = None) -> None:
        """Connect the ports: ``refs`` port -> absolute key, ``literals`` port -> constant.

        Ports in neither use ``DEFAULT_KEYS`` (resolved inside ``namespace``), else their declared
        default as a constant, else a private key that nothing writes: under the node's name and
        ``private_tag`` (the tree builder's number for it, the same every build; see
        _scoped_node_name).
        """
        if private_tag is not None:
            self.private_tag = private_tag
        refs = dict(refs or {})
        literals = dict(literals or {})
        for port, key in self.DEFAULT_KEYS.items():
            if port not in refs and port not in literals:
                refs[port] = namespaced(namespace, key)
        # An unwired input is private to this node, so nothing can ever write it: its declared
        # default is a constant (and reading it needs no blackboard look-up).
        for port, info in self.input_ports().items():
            if port not in refs and port not in literals and info.has_default:
                literals[port] = copy.deepcopy(info.default_value)
        self.namespace = namespace
        self._literals = literals
        self.setup_ports(port_remappings=refs, subtree_namespace=namespace)
        # Resolve every port to its storage key once: the hot path then reads and writes the
        # (process-global) py_trees storage directly, keeping the tick overhead small.
        self._keys = {p: self._get_blackboard_key(p)
                      for p in (*self.input_ports(), *self.output_ports()) if p not in literals}
        # the class each wired input must hold (ports typed with something else go unchecked)
        self._types = {p: info.data_type for p, info in self.input_ports().items()
                       if p in self._keys and isinstance(info.data_type, type)}
        # wired number inputs: range-checked on read (literals were checked at load time)
        self._ranged = {p: info for p, info in self.input_ports().items()
                        if p in self._keys and info.data_type in (float, int)}
        # the class each wired output must be given (ports typed with something else: any)
        self._out_types = {p: info.data_type for p, info in self.output_ports().items()
                           if p in self._keys and isinstance(info.data_type, type)}

    def _scoped_node_name(self) -> str:
        """Where the private keys of unwired ports live: ``<scope>/<name>_<private_tag>``.

        py_trees appends a uuid4, which differs every run and so would make two runs of one
        tree record different keys; the builder's tag is unique within the tree and the same
        every time the tree is built (the mission namespace keeps two loaded trees apart).
        """
        tag = self.private_tag
        if tag is None:
            return super()._scoped_node_name()
        namespace = (self._subtree_namespace or "/").rstrip("/")
        return f"{namespace}/{sanitize_name_for_blackboard_use(self.name)}_{tag}"

    def _fast_get(self, port_name: str) -> Any:
        """Stored value of a wired port, _MISSING when absent (None counts as absent)."""
        value = _BB.storage.get(self._keys[port_name], _MISSING)
        if value is None:
            return _MISSING
        if value is not _MISSING:
            expected = self._types.get(port_name)
            if expected is not None and not isinstance(value, expected):
                raise TypeError(f"{type(self).__name__} '{self.name}': port '{port_name}' "
                                f"({self._keys[port_name]}) holds {type(value).__name__}, "
                                f"expected {expected.__name__}")
            info = self._ranged.get(port_name)
            if info is not None:
                problem = port_problem(info, value)
                if problem is not None:
                    raise ValueError(f"{type(self).__name__} '{self.name}': port '{port_name}' "
                                     f"({self._keys[port_name]}) {problem}")
        return value

    def get_input(self, port_name: str, default: Any = None) -> Any:
        """The port's literal if it has one, else the blackboard value, else its default."""
        value = self._literals.get(port_name, _MISSING)
        if value is not _MISSING:
            return value
        keys = getattr(self, "_keys", None)
        if keys is None or port_name not in keys:
            return super().get_input(port_name, default)
        value = self._fast_get(port_name)
        if value is not _MISSING:
            return value
        if default is not None:
            return default
        info = self.input_ports()[port_name]
        if info.has_default:
            return copy.deepcopy(info.default_value)
        raise NoDataAvailable(f"{self.name}: input port '{port_name}' ({keys[port_name]}) has "
                              f"no data")

    def read(self, port_name: str) -> Any:
        """Like ``get_input`` but None when no data is available yet (no exception)."""
        keys = getattr(self, "_keys", None)
        if keys is not None and port_name in keys:  # (literal ports have no key)
            value = self._fast_get(port_name)  # the usual case, one call less
            if value is not _MISSING:
                return value
        try:
            return self.get_input(port_name)
        except (NoDataAvailable, NotImplementedError):  # py_trees refuses stored None values
            return None

    def write(self, port_name: str, value: Any) -> None:
        """Write an output port (type-checked)."""
        keys = getattr(self, "_keys", None)
        if keys is None or port_name not in keys:
            self._set_output(port_name, value)
            return
        expected = self._out_types.get(port_name)
        if expected is not None and not isinstance(value, expected):
            raise TypeError(f"{type(self).__name__} '{self.name}': port '{port_name}' takes "
                            f"{expected.__name__}, got {type(value).__name__}")
        _BB.storage[keys[port_name]] = value

    def port_key(self, port_name: str) -> str:
        """The absolute blackboard key behind a port (for messages and tests)."""
        return self._get_blackboard_key(port_name)

    # ---------------------------------------------------------------- components
    def component(self, kwargs: dict[str, Any], key: str, optional: bool = False) -> Any:
        """Fetch ``key`` from the ``setup`` kwargs or raise ComponentError naming the node."""
        if key in kwargs and kwargs[key] is not None:
            return kwargs[key]
        if optional:
            return None
        raise ComponentError(f"{type(self).__name__} '{self.name}': setup() needs component "
                             f"'{key}' (see behaviors/components.py)")

    def say(self, message: str, *args: Any) -> None:
        """Set the feedback message; with ``args`` it is ``message.format(*args)``, formatted
        when first read (a message set every tick then costs no float formatting). Pass only
        immutable values (numbers, strings) as ``args``."""
        self._feedback = (message, args) if args else message

    @property
    def feedback_message(self) -> str:
        """py_trees' feedback message (the text of the last ``say``)."""
        message = self._feedback
        if message.__class__ is tuple:
            message = self._feedback = message[0].format(*message[1])
        return message

    @feedback_message.setter
    def feedback_message(self, message: str) -> None:
        self._feedback = message

    @classmethod
    def describe(cls) -> str:
        """First line of the class docstring."""
        return (cls.__doc__ or "").strip().splitlines()[0] if cls.__doc__ else ""


class Recovery:
    """Marks a node whose start means "a recovery fired" (logs, pictures, summaries).

    Put it first among a node's bases; it works for navbt nodes and plain py_trees behaviours
    alike. Each start of a run (a tick while not RUNNING) adds one to ``recovery_starts``; the
    executive compares the counts after each tick, so nothing is wrapped or replaced.
    """

    recovery_starts: int = 0

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        # counted when the tick runs, not when the generator is made (py_trees' stop makes one)
        if self.status is not RUNNING:  # type: ignore[attr-defined]
            self.recovery_starts += 1
        yield from super().tick()  # type: ignore[misc]


class Leaf(NavNode, py_trees.behaviour.Behaviour):
    """Base of actions and conditions (no children): implement ``initialise``/``update``/
    ``terminate`` as for any py_trees behaviour.

    ``tick`` is py_trees' ``Behaviour.tick`` (initialise when not RUNNING, update, stop on a
    final status, yield self) without its per-tick debug formatting, which dominated the tick
    cost. An exception raised by ``initialise`` or ``update`` leaves the tick: a bug is not a
    navigation failure (the executive ends the mission with INTERNAL_ERROR).
    """

    def tick(self) -> Iterator[py_trees.behaviour.Behaviour]:
        if self.status is not RUNNING:
            self.initialise()
        new_status = self.update()
        if new_status.__class__ is not Status:  # no set look-up: Enum hashes in Python
            self.logger.error(f"{self.name}: update() returned {new_status!r}, not a Status")
            new_status = INVALID
        if new_status is not RUNNING:
            self.terminate(new_status)  # what stop() does, less a call
        self.status = new_status
        yield self

    def stop(self, new_status: Status = INVALID) -> None:
        self.terminate(new_status)
        self.status = new_status


class ParentTick:
    """``begin_tick`` and ``finish`` for nodes whose ``tick`` ticks their children (``Control``,
    ``DecoratorNode``); ``halt_children()`` stops the children that are not INVALID."""

    def begin_tick(self) -> bool:
        """First thing in ``tick``: True when this tick starts a new run (this node not
        RUNNING), having stopped the children that are not INVALID."""
        if self.status is RUNNING:  # type: ignore[attr-defined]
            return False
        self.halt_children()  # type: ignore[attr-defined]
        return True

    def finish(self, status: Status) -> ParentTick:
        """End this tick with ``status`` (a final one stops this node); this node, for
        ``yield self.finish(status)``."""
        if status is RUNNING:
            self.status = RUNNING
        else:
            self.stop(status)  # type: ignore[attr-defined]
        return self


class Control(ParentTick, NavNode, py_trees.composites.Composite):
    """Base of control nodes: subclasses implement ``tick`` as py_trees' composites do.

    Tick semantics are py_trees' (docs/trees.md, "How a tick works"): ``tick`` is a generator
    yielding every node ticked, each as it finishes, then this node. It starts with
    ``begin_tick()``: a tick that starts a new run (this node not RUNNING) first stops every child
    that is not INVALID, as py_trees' Sequence and Selector do, so the run starts them afresh.
    It ticks children (``yield from child.tick()``) and ends with ``yield
    self.finish(status)``: a final status stops this node: children still RUNNING are stopped
    (INVALID), finished ones keep their status for introspection until the next run (py_trees;
    BT.CPP resets them at once, which gives the same behaviour on the next tick).
    ``stop(INVALID)`` (a halt) stops every child. (One generator per node and tick: each
    yield passes through every ancestor's generator, so a second one per node would cost.)

    ``MIN_CHILDREN``/``MAX_CHILDREN`` are checked by the loader (STYLE 2.5) and at construction.
    """

    CATEGORY = "Control"
    MIN_CHILDREN: ClassVar[int] = 1
    MAX_CHILDREN: ClassVar[int | None] = None

    def __init__(self, name: str = "", children: Iterable[py_trees.behaviour.Behaviour] | None = None,
                 **kwargs: Any) -> None:
        super().__init__(name=name, children=list(children or []), **kwargs)

    def tick(self) -> Ticking:
        """Tick children for this tick (``yield from child.tick()``), then end it with
        ``yield self.finish(status)``; start with ``self.begin_tick()``."""
        raise NotImplementedError(f"{type(self).__name__}: no tick")
        yield  # (a generator)

    def halt_children(self, start: int = 0) -> None:
        """Stop (INVALID) every child from index ``start`` on that is not INVALID."""
        for child in self.children[start:]:
            if child.status is not INVALID:
                child.stop(INVALID)

    def stop(self, new_status: Status = INVALID) -> None:
        # py_trees' Composite.stop (less its debug formatting, a large part of a tick's cost)
        # plus what py_trees' Parallel and Sequence do before finishing: no child left RUNNING.
        if new_status is INVALID:
            self.current_child = None
            self.halt_children()
        else:
            for child in self.children:
                if child.status is RUNNING:
                    child.stop(INVALID)
        self.terminate(new_status)
        self.status = new_status


class DecoratorNode(ParentTick, NavNode, py_trees.decorators.Decorator):
    """Base of decorators that decide *whether* and *how* to tick their child (``tick``,
    with ``begin_tick`` and ``finish`` as in ``Control``): a new run stops the child if it is not
    INVALID; a final status stops a RUNNING child; a halt stops the child."""

    CATEGORY = "Decorator"

    def __init__(self, name: str = "", child: py_trees.behaviour.Behaviour | None = None,
                 **kwargs: Any) -> None:
        if child is None:
            raise TypeError(f"{type(self).__name__} '{name}': a decorator needs a child")
        super().__init__(name=name, child=child, **kwargs)

    def tick(self) -> Ticking:
        """Tick the child or not (``yield from self.decorated.tick()``), then end the tick with
        ``yield self.finish(status)``; start with ``self.begin_tick()``."""
        raise NotImplementedError(f"{type(self).__name__}: no tick")
        yield  # (a generator)

    def update(self) -> Status:
        """Unused: these decorators decide in ``tick`` (py_trees declares it abstract)."""
        return self.decorated.status

    def halt_children(self) -> None:
        if self.decorated.status is not INVALID:
            self.decorated.stop(INVALID)

    def stop(self, new_status: Status = INVALID) -> None:
        # py_trees' Decorator.stop: the child is stopped on a halt or when still RUNNING
        self.terminate(new_status)
        if new_status is INVALID or self.decorated.status is RUNNING:
            self.halt_children()
        self.status = new_status


def node_classes() -> dict[str, type[NavNode]]:
    """Every registered navbt node class by tag (imports the whole library first)."""
    import behaviors.library  # noqa: F401  (registers every node class)
    return {tag: cls for tag, cls in get_ports_registry().items() if issubclass(cls, NavNode)}


def make(node_type: str | type[NavNode], name: str = "", namespace: str = "/test",
         children: list[py_trees.behaviour.Behaviour] | None = None,
         child: py_trees.behaviour.Behaviour | None = None,
         port_values: dict[str, Any] | None = None, nav2_distro: str | None = None,
         **ports: Any) -> NavNode:
    """Build and wire one node by hand (tests): ``"{key}"`` strings are references.
    ``port_values`` carries ports whose names clash with these arguments (``namespace``);
    ``nav2_distro`` reaches the nodes that follow one (``USES_NAV2_DISTRO``), as the loader's.

    >>> make("Wait", wait_duration=2.0)            # doctest: +SKIP
    """
    ports = {**ports, **(port_values or {})}
    cls = node_classes()[node_type] if isinstance(node_type, str) else node_type
    kwargs: dict[str, Any] = {}
    if issubclass(cls, Control):
        kwargs["children"] = children or []
    elif issubclass(cls, DecoratorNode):
        kwargs["child"] = child
    if cls.USES_NAV2_DISTRO:
        kwargs["nav2_distro"] = nav2_distro
    node = cls(name=name or cls.__name__, **kwargs)
    refs, literals = {}, {}
    for port, value in ports.items():
        if port not in cls.input_ports() and port not in cls.output_ports():
            raise KeyError(f"{cls.__name__}: no port '{port}'")
        if isinstance(value, str) and value.startswith("{") and value.endswith("}"):
            refs[port] = namespaced(namespace, value[1:-1])
        else:
            info = cls.input_ports().get(port)
            if info is not None and info.data_type is float and isinstance(value, int):
                value = float(value)
            literals[port] = value
    node.wire(namespace, refs, literals)
    return node
