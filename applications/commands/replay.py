"""`interbot replay FILE.mcap`: re-run an application's decisions on a recording's inputs."""
from __future__ import annotations

import signal
import threading
import time

from applications import observing
from applications.commands.arguments import UsageError
from applications.commands.refusals import positive_speed, recording_file
from applications.exceptions import ApplicationError
from applications.shutdown import HANDLED_SIGNALS


class ReplayCommand:
    name = "replay"
    help = ("re-run an application on a recording's inputs (no robot) and report the first tick "
            "where a decision differs")

    def add_arguments(self, parser) -> None:
        parser.add_argument("recording", type=recording_file, help="an MCAP file written by `interbot run --record`")
        parser.add_argument("--app", help="replay this application (a bundled name or a folder) "
                                          "instead of the recorded one, e.g. a changed copy")
        parser.add_argument("--speed", type=positive_speed, default=None,
                            help="robot seconds per wall second (default: as fast as possible; "
                                 "1 with --inspect)")
        parser.add_argument("--all", action="store_true",
                            help="replay to the end instead of stopping at the first divergence")
        observing.add_arguments(parser, record=False)

    def run(self, args) -> int:
        from applications.dialog import load_dialog
        from applications.graph.catalog import load_catalog
        from applications.graph.loader import load_application
        from applications.recording import open_recording
        from applications.replay import (Comparator, Diverged, ReplayEnded, ReplayFeed,
                                         application_folder, replay_duration)
        from applications.runtime import Run
        from behaviors.robot import open_robot

        try:
            recording = open_recording(args.recording)
        except ApplicationError as exc:     # cut inside its first chunk, unreadable: a mistake
            raise UsageError(f"argument recording: {exc}") from exc
        meta = recording.meta
        if not meta.get("robot") or "duration" not in meta:
            raise UsageError("argument recording: "
                             f"{recording.path} is an MCAP file but not an interbot "
                             f"recording (no 'interbot' metadata with robot and duration)")
        folder = application_folder(recording, args.app)
        robot_name = meta.get("robot")
        app = load_application(folder, robot=robot_name)
        dialog = load_dialog(folder / "dialog.xml", app.states, load_catalog(robot_name).behaviors)
        feed = ReplayFeed(recording)
        pose = meta.get("initial_pose")
        robot = open_robot(robot_name, replay=feed, seed=int(meta.get("seed") or 0),
                           map=meta.get("map"), initial_pose=tuple(pose) if pose else None)
        comparator = Comparator(feed, stop=not args.all,
                                explain=_explainer(recording, folder, app, robot_name))
        print(f"interbot: replaying {recording.path} ({meta.get('app')} on {robot_name}) "
              f"with {folder}", flush=True)
        watching = None
        summary = None
        status = 0
        try:
            watching = observing.open_observers(args, app=app, folder=folder, robot=robot,
                                                robot_name=robot_name, meta={}, controls=True,
                                                layout=recording.map)
            speed = args.speed if args.speed is not None else (1.0 if args.inspect else None)
            # the comparator last: the inspector has shown a diverging tick before it stops
            observers = ([RecordedTruth(feed)] if watching.inspector else []) + watching.observers \
                + ([Pacer(speed)] if speed else []) + [comparator]
            run = Run(app, robot, dialog=dialog, duration=replay_duration(recording),
                      echo=None, observers=observers)
            try:
                summary = run.run()
            except Diverged:
                pass
            except ReplayEnded as end:
                print(f"interbot: {end}", flush=True)
            if watching.inspector is not None:
                _keep_serving(comparator)
        finally:
            if watching is not None:
                watching.close(summary)
            robot.close()
        if comparator.first is not None:
            print("\n".join(comparator.first.lines()))
            status = 1
        else:
            print(f"no divergence in {comparator.compared} ticks")
        return status


def _explainer(recording, folder, app, robot_name):
    """`explain(recorded, replayed, previous)` comparing the recorded application (when its
    folder is still there) with the replayed one."""
    from pathlib import Path

    from applications.divergence import explain
    from applications.exceptions import ApplicationError as Refused
    from applications.graph.loader import load_application

    recorded_app = app
    original = recording.meta.get("folder")
    if original and Path(original).resolve() != Path(folder).resolve():
        try:
            recorded_app = load_application(Path(original), robot=robot_name)
        except (Refused, OSError):
            recorded_app = None      # gone or changed since: the recorded condition texts
    return lambda recorded, replayed, previous: explain(recorded, replayed, previous,
                                                        recorded_app, app)


def _keep_serving(comparator) -> None:
    """Leave the inspector up on the last tick (a divergence) until the user is done.

    Ctrl-C, SIGTERM and SIGHUP end the wait through handlers of our own, so that the replay
    then closes its inspector and recording as after any replay: a SIGTERM used to end the
    process on the spot, and a SIGINT that whoever started us had set to be ignored (Python
    then installs no KeyboardInterrupt) was never seen."""
    done = threading.Event()
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in HANDLED_SIGNALS:
            previous[signum] = signal.signal(signum, lambda *_: done.set())
    try:
        if comparator.first is not None:
            print("\n".join(comparator.first.lines()))
        print("interbot: the replay is over; the inspector shows its last tick until Ctrl-C",
              flush=True)
        while not done.wait(1.0):
            pass
    except KeyboardInterrupt:        # from a handler installed around ours, if any
        pass
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


class RecordedTruth:
    """Puts the recorded true people into the replayed tick, for the inspector's top view
    (a replay has no simulation of its own)."""

    def __init__(self, feed) -> None:
        self.feed = feed

    def __call__(self, snapshot) -> None:
        robot = snapshot.get("robot")
        if robot is None:
            return
        for messages in self.feed.recorded:
            if messages["/interbot/tick"]["tick"] == snapshot["tick"]:
                truth = messages.get("/interbot/hardware", {}).get("truth", [])
                robot["skills"]["hardware"]["truth"] = truth
                return


class Pacer:
    """Holds the replay to `speed` robot seconds per wall second (to watch it)."""

    robot_snapshot = False

    def __init__(self, speed: float) -> None:
        self.speed = speed
        self._start: tuple[float, float] | None = None

    def __call__(self, snapshot) -> None:
        if self._start is None:
            self._start = (time.monotonic(), snapshot["t"])
            return
        wall0, t0 = self._start
        delay = wall0 + (snapshot["t"] - t0) / self.speed - time.monotonic()
        if delay > 0:
            time.sleep(delay)
