"""A camera as a person detector: frames through OpenCV, people and faces found by the detectors
OpenCV ships, turned into robot-frame positions with the camera's calibration."""
