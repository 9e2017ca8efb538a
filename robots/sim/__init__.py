"""The simulated world of L0: office and store floors, a unicycle body, ray-cast sonar and
laser, and simulated people who follow a scenario file. Everything is numpy and deterministic
for a seed.

Modules: `raycast` (pure geometry), `floor` (walls and places from TOML), `body` (the robot's
motion), `scenario` (the people's script, from TOML), `people` (people following that script),
`walkways` (people's routes around walls), `measures` (clearances, contacts, intrusions),
`world` (all of it stepped together), `devices` and `base` (the L0 interfaces over a world),
`simulation` (wiring a world to a clock). Example scenarios are in `examples/`.
"""
