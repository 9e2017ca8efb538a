"""Campaigns (issue 27): a grid of `interbot run`s — application, robots, maps, scenario
families, seeds, learner settings — from one TOML spec, run many at once, resumable, each run's
summary kept, all results in one SQLite table with a summary and plots.

- `spec`     the TOML file and the grid of runs it makes
- `engine`   one run (exactly an `interbot run` in its own process) and the engines that spread
             them: local processes, or Ray (`pip install interbot[cluster]`)
- `results`  the results database: what ran, what it gave, what is left to run
- `plots`    the learning curves of the strategies compared
- `command`  `interbot campaign SPEC.toml`
"""
