"""A camera looking at the simulated world: the people it would see, drawn (robots.camera.render)
and served as an MJPEG stream over HTTP, which OpenCV opens like a network camera.

`WorldCamera` renders one frame from the world as it is: each person's bearing and distance
from the camera (the body's pose, the camera's mounting, and the world's head pan when the
camera is on the head), nearest drawn last so they hide those behind. It is a plain picture:
walls do not hide people, the camera sits at half a person's height, and nobody is drawn
closer than 0.3 m. What it leaves out: docs/emulator-fidelity.md.

`CameraEmulator` (`interbot emulate camera --tcp PORT`) serves the newest frame at FPS frames
a second to every client of http://HOST:PORT/video.mjpg, and steps the world in real time.
`WorldFrameSource` hands the frames to a camera pipeline in the same process (a simulated run
whose profile names a camera device).
"""
from __future__ import annotations

import math
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

from robots.camera.intrinsics import Intrinsics
from robots.camera.render import render, shirt_colour
from robots.profile import CameraSpec
from robots.sim.appearance import appearance_of

FPS = 10.0
PATH = "/video.mjpg"
BOUNDARY = b"frame"


class WorldCamera:
    """What a camera of `spec` sees of `world` now."""

    def __init__(self, world, spec: CameraSpec, lens: Intrinsics) -> None:
        self.world = world
        self.spec = spec
        self.lens = lens

    def pose(self) -> tuple[float, float, float]:
        """The camera's position and viewing direction in the world frame."""
        body, spec = self.world.body, self.spec
        c, s = math.cos(body.th), math.sin(body.th)
        heading = body.th + spec.heading + (self.world.head_pan if spec.on_head else 0.0)
        return body.x + c * spec.x - s * spec.y, body.y + s * spec.x + c * spec.y, heading

    def visible(self) -> list[tuple[float, float, tuple[int, int, int]]]:
        """(distance, bearing, shirt colour) of each person in the field of view."""
        x, y, heading = self.pose()
        half = math.atan(self.lens.width / 2 / self.lens.fx)
        out = []
        for person_id, px, py in self.world.ground_truth():
            distance = math.hypot(px - x, py - y)
            bearing = math.remainder(math.atan2(py - y, px - x) - heading, math.tau)
            if abs(bearing) < half + 0.2 and 0.3 < distance <= self.spec.max_range:
                out.append((distance, bearing, shirt_colour(appearance_of(person_id))))
        return out

    def frame(self):
        return render(self.lens, self.visible())


class WorldFrameSource:
    """A `FrameSource` stand-in in the simulated world's own process: a new rendered frame
    every 1/FPS s of the clock (the simulated one in `--fast` runs: deterministic)."""

    def __init__(self, camera: WorldCamera, clock, fps: float = FPS) -> None:
        self.camera = camera
        self.clock = clock
        self.fps = fps
        self.frames = 0
        self._newest = None
        self._due = -math.inf

    def open(self) -> None:
        """Nothing to open: the world is here."""

    def read(self):
        from robots.camera.source import Frame
        now = self.clock.now()
        if now + 1e-9 >= self._due:
            self.frames += 1
            self._newest = Frame(now, self.frames, self.camera.frame())
            self._due = now + 1.0 / self.fps
        return self._newest

    def fault(self) -> str | None:
        return None

    def close(self) -> None:
        """Nothing to close."""


class CameraEmulator:
    """Serves a `WorldCamera` as MJPEG over HTTP (TCP only: there is no serial line)."""

    name = "camera-emulator"

    def __init__(self, camera: WorldCamera, clock=None, fps: float = FPS) -> None:
        self.camera = camera
        self.clock = clock
        self.fps = fps
        self.frames = 0
        self._jpeg: bytes | None = None
        self._cond = threading.Condition()
        self._stop = threading.Event()
        self._server: ThreadingHTTPServer | None = None
        self._threads: list[threading.Thread] = []

    @classmethod
    def for_profile(cls, profile, world, clock=None, **_) -> "CameraEmulator":
        """The profile's [camera] (a default EVI-D31-sized view without one), on the head if
        the robot has one."""
        spec = profile.camera or CameraSpec(on_head=profile.head is not None)
        lens = Intrinsics.from_fov(spec.hfov_deg, spec.width, spec.height)
        return cls(WorldCamera(world, spec, lens), clock)

    # -- the emulate command's interface ---------------------------------------------------------
    def attach(self, simulation) -> None:
        """Nothing to hook: frames are rendered from the world as it is."""

    def serve_pty(self, link=None) -> str:
        raise OSError("a camera is served over TCP (an MJPEG stream), not on a pty")

    def serve_tcp(self, host: str = "127.0.0.1", port: int = 0) -> tuple[str, int]:
        emulator = self

        class Stream(BaseHTTPRequestHandler):
            def log_message(self, *args) -> None:
                pass

            def do_GET(self) -> None:
                if self.path != PATH:
                    self.send_error(404, f"the stream is at {PATH}")
                    return
                self.send_response(200)
                self.send_header("Content-Type",
                                 f"multipart/x-mixed-replace; boundary={BOUNDARY.decode()}")
                self.end_headers()
                emulator._stream_to(self.wfile)

        self._server = ThreadingHTTPServer((host, port), Stream)
        self._server.daemon_threads = True
        self._spawn(self._server.serve_forever, f"{self.name}-http")
        return self._server.server_address[:2]

    def start_clock(self, simulation=None) -> None:
        """Step the world in real time (when given) and render FPS frames a second."""
        def now() -> float:
            return self.clock.now() if self.clock is not None else time.monotonic()

        def run() -> None:
            while not self._stop.wait(1.0 / self.fps):
                if simulation is not None:
                    simulation.advance(now())
                self.publish()
        self._spawn(run, f"{self.name}-clock")

    def publish(self) -> None:
        """Render the world now and hand the frame to the clients."""
        import cv2
        ok, jpeg = cv2.imencode(".jpg", self.camera.frame())
        if ok:
            with self._cond:
                self._jpeg = jpeg.tobytes()
                self.frames += 1
                self._cond.notify_all()

    def _stream_to(self, out) -> None:
        sent = 0
        while not self._stop.is_set():
            with self._cond:
                self._cond.wait_for(lambda: self.frames > sent or self._stop.is_set(), 1.0)
                jpeg, sent = self._jpeg, self.frames
            if jpeg is None:
                continue
            try:
                out.write(b"--" + BOUNDARY + b"\r\nContent-Type: image/jpeg\r\nContent-Length: "
                          + str(len(jpeg)).encode() + b"\r\n\r\n" + jpeg + b"\r\n")
            except OSError:          # the client left
                return

    def _spawn(self, target, name: str) -> None:
        thread = threading.Thread(target=target, name=name, daemon=True)
        self._threads.append(thread)
        thread.start()

    def close(self) -> None:
        self._stop.set()
        with self._cond:
            self._cond.notify_all()
        if self._server is not None:
            self._server.shutdown()
            self._server.server_close()
        for thread in self._threads:
            thread.join(timeout=2.0)
        self._threads.clear()
