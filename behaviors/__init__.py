"""L2, abstraction: macro-behaviors as py_trees subtrees over skills, their robot-specific
realizations, the behavior registry, and the read-only percept view L3 conditions use.
Imports only `skills` (L1)."""
