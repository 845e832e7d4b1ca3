"""BehaviorTree.CPP 4 built-in nodes beyond navbt's first set (issue 19). Importing this
package registers them."""

from behaviors.btcpp import sequence_star  # noqa: F401
