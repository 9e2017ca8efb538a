"""The learner of the dialog manager (issue 27): at each choice point of `dialog.xml` it picks
an alternative (`first`, `random`, `rotate`, or `learn` — a multi-armed bandit per choice point
and context), watches the success condition, and keeps every episode in the application's
SQLite database, so what was learned survives restarts and `kill -9`.

- `bandit`  the arithmetic: Thompson sampling, UCB1, exploit-only, minimum share, intervals
- `store`   the episodes and settings (frozen, minimum share) in SQLite
- `chooser` the run-time side: choose on entering a state, watch success, write outcomes
- `report`  what `interbot learn APP` prints and draws
"""
