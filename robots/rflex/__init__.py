"""rFLEX: the serial protocol of the RWI/iRobot B21r base (PERSES).

`protocol` is the pure codec and byte-fed parser, `driver` the host side (`RFlexBase`),
`emulator` the controller side for tests and the simulated world.
"""
