"""CANopen (CiA 301 / CiA 402): a differential-drive base with two wheel drives on a CAN bus.

`protocol` is the pure codec of the services used, `wheels` the drive parameters and
kinematics, `od` the drives' object dictionary, `bus` port parsing and the session log,
`driver` the `Base` over python-can, `emulator` the two drives for tests and the simulated
world, `socketcand` the TCP server that `interbot emulate can` puts the emulated bus on.
"""
