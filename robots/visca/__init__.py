"""Sony VISCA pan-tilt camera heads (EVI-D31, EVI-D70): codec, driver and emulator."""
