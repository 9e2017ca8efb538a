"""L0, hardware: base drivers, device emulators, the simulated world and robot profiles.

`robots` imports none of the other interbot layers. `skills` (L1) is its only client.
"""
