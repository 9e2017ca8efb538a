"""The tablet page in headless Chromium: how fast a question appears, a touch counts, and the
screen follows a change.

- question → visible: from `show()` on the robot's side to the buttons being in the page and a
  frame painted (the browser reports it through WebDriver, so this is an upper bound);
- click → answer: from the page seeing the touch (pointerdown, the browser's clock) to the answer
  on the blackboard (`survey/progress`, written by the questionnaire), with the skills sensing
  at 10 Hz on the real clock as in `interbot run`; the baseline is the same touch to the press
  arriving in the device's queue (no tick to wait for): the difference is the wait for a tick
  (touches fall at random moments of the tick, as a person's would);
- update rate: the caption changed at 50 Hz for a few seconds; screens the page rendered per s.

    python benchmarks/bench_tablet.py [--rounds 40]

Benchmarks are not a layer: this script opens the skills (L1) and the page (L0) directly.
"""
from __future__ import annotations

import argparse
import os
import random
import statistics
import sys
import threading
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from selenium.webdriver.common.by import By   # noqa: E402

from skills.questionnaire import Question     # noqa: E402
from skills.skillset import open_skills       # noqa: E402
from tests.browser import chromium            # noqa: E402

TICK = 0.1

WAIT_FOR_PROMPT = """
const [prompt, done] = arguments;
function ready() {
  const section = document.getElementById('question');
  return document.getElementById('screen').dataset.mode === 'question'
      && section.dataset.prompt === prompt
      && document.querySelectorAll('#buttons button').length > 0;
}
function check() {
  if (ready()) { requestAnimationFrame(() => done(performance.now())); }
  else { setTimeout(check, 1); }
}
check();
"""

# When the page saw the touch (Unix time, s): a capturing listener the benchmark adds itself.
MARK_TOUCHES = """
window.touchedAt = [];
document.addEventListener('pointerdown',
    () => window.touchedAt.push((performance.timeOrigin + performance.now()) / 1000), true);
"""

COUNT_RENDERS = """
const [seconds, done] = arguments;
const main = document.getElementById('screen');
let renders = 0;
const observer = new MutationObserver(() => { renders += 1; });
observer.observe(main, {attributes: true, attributeFilter: ['data-version']});
setTimeout(() => { observer.disconnect(); done(renders); }, seconds * 1000);
"""


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(round(q / 100 * (len(ordered) - 1))))]


def summary(name: str, seconds: list[float]) -> str:
    ms = [1000 * s for s in seconds]
    return (f"{name:<38} median {statistics.median(ms):7.1f} ms   p95 {percentile(ms, 95):7.1f} ms"
            f"   p99 {percentile(ms, 99):7.1f} ms   (n={len(ms)})")


class Ticker:
    """The skills sensing at 10 Hz in their own thread, noting when each answer arrived."""

    def __init__(self, skills) -> None:
        self.skills = skills
        self.answered_at: dict[str, float] = {}     # question -> Unix time on the blackboard
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)
        self.lock = threading.Lock()

    def run(self) -> None:
        next_tick = time.monotonic()
        while not self.stop.is_set():
            with self.lock:
                self.skills.sense()
                progress = self.skills.blackboard.value("survey/progress")
            stamp = time.time()
            for question, _ in (progress.answers if progress is not None else ()):
                self.answered_at.setdefault(question, stamp)
            next_tick += TICK
            time.sleep(max(0.0, next_tick - time.monotonic()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    skills = open_skills("horos", gui="127.0.0.1:0")
    page = skills.hardware.screen.screens[1]
    questions = tuple(Question(f"q{i}", f"Question number {i}?", ("yes", "no"))
                      for i in range(args.rounds))
    visible, clicked, queued = [], [], []
    phases = random.Random(0)
    try:
        with chromium() as driver:
            driver.set_script_timeout(30)
            driver.get(skills.tablet_url)
            driver.execute_script(MARK_TOUCHES)
            time.sleep(1.0)
            # 1. question decided -> buttons visible, and 2. click -> answer in the questionnaire
            ticker = Ticker(skills)
            with ticker.lock:
                skills.questionnaire.load(questions, skills.now())
            ticker.thread.start()
            for question in questions:
                shown_at: list[float] = []

                def ask(question=question, shown_at=shown_at):
                    time.sleep(0.02)
                    with ticker.lock:
                        shown_at.append(time.perf_counter())
                        skills.questionnaire.ask_next(skills.now())
                timer = threading.Thread(target=ask)
                timer.start()
                driver.execute_async_script(WAIT_FOR_PROMPT, question.id)
                visible.append(time.perf_counter() - shown_at[0])
                timer.join()
                time.sleep(phases.uniform(0.0, TICK))   # touch at any moment of the tick
                driver.find_element(By.CSS_SELECTOR, "#buttons button").click()
                while question.id not in ticker.answered_at:
                    time.sleep(0.001)
                touched = driver.execute_script("return window.touchedAt.at(-1)")
                clicked.append(ticker.answered_at[question.id] - touched)
            ticker.stop.set()
            ticker.thread.join()
            # baseline: click -> press in the device's queue (no tick in between)
            for i in range(args.rounds):
                page.show(f"b{i}", "Baseline?", ("yes", "no"))
                driver.execute_async_script(WAIT_FOR_PROMPT, f"b{i}")
                driver.find_element(By.CSS_SELECTOR, "#buttons button").click()
                while page.take_press() is None:
                    time.sleep(0.0005)
                arrived = time.time()
                queued.append(arrived - driver.execute_script("return window.touchedAt.at(-1)"))
            # 3. update rate while the caption changes at 50 Hz
            seconds, changes = 3.0, [0]

            def change():
                end = time.monotonic() + seconds + 0.5
                while time.monotonic() < end:
                    changes[0] += 1
                    page.caption(f"Counting {changes[0]}")
                    time.sleep(0.02)
            changer = threading.Thread(target=change)
            changer.start()
            time.sleep(0.2)
            renders = driver.execute_async_script(COUNT_RENDERS, seconds)
            changer.join()
    finally:
        skills.close()
    print(f"bench_tablet: headless Chromium, {args.rounds} rounds; load average "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}; {os.cpu_count()} CPUs")
    print(summary("question -> buttons visible", visible))
    print(summary("touch -> answer on blackboard (10 Hz)", clicked))
    print(summary("touch -> press queued (baseline)", queued))
    print(f"{'screen updates while changing':<38} {renders / seconds:7.1f} Hz "
          f"(caption changed at ~{changes[0] / (seconds + 0.5):.0f} Hz)")


if __name__ == "__main__":
    main()
