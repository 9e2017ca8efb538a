"""L1, skills: the py_trees blackboard and its key schema, and the skills that read sensors and
drive actuators (perception, motion, speech, head, survey dialog). Imports only `robots` (L0)."""
