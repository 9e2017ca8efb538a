"""The tablet page in a real browser (headless Chromium) during a real-time simulated survey:
a person answers every question by clicking, while the simulated person only stands there.

Two runs cover the whole story: the page needs its token, two tabs show the same question, a
reloaded tab gets the current screen back, the screenshot shows the question; then the robot's
process is killed mid-question (the page says the robot is not running and shows no question),
a new run starts on the same port with a new token, and the same page, with its old address,
finds it again (the tablet was paired): the answers clicked there arrive in SQLite and in the
trace as `touch` answers. The last run is stopped by SIGINT once the survey is done, instead of
waiting out its duration.
"""
from __future__ import annotations

import io
import os
import re
import shutil
import signal
import socket
import sqlite3
import subprocess
import sys

import pytest
from PIL import Image
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

from applications.graph.loader import find_application
from applications.trace import read_trace
from tests.browser import chromium

# A person who walks up to the robot and stays, never touching the simulated screen.
SILENT_PERSON = """
[scenario]
name = "silent"
duration = 60.0
robot = "robot_home"
[[person]]
id = "visitor"
appear = 0.1
at = [0.9, 0.2]
speed = 1.0
steps = [ { approach = 0.5 }, { pause = 300.0 } ]
"""
ANSWERS = {"q1": "yes", "q2": "4", "q3": "no"}
RUN_SECONDS = "60"          # a bound only: the test ends the runs itself


@pytest.fixture
def quick_survey(tmp_path):
    """The bundled survey, waiting 0.2 s instead of 30 s before it attracts a new person."""
    folder = tmp_path / "survey"
    shutil.copytree(find_application("survey"), folder)
    graph = folder / "graph.xml"
    text = graph.read_text()
    assert "time_in_state > 30s and people.new" in text
    graph.write_text(text.replace("time_in_state > 30s and people.new",
                                  "time_in_state > 0.2s and people.new"))
    scenario = tmp_path / "silent.toml"
    scenario.write_text(SILENT_PERSON)
    return folder, scenario


def shown(driver) -> dict:
    """What the page shows, read in one go (the page may re-render between two WebDriver calls)."""
    return driver.execute_script("""
        const section = document.getElementById('question');
        return {mode: document.getElementById('screen').dataset.mode,
                prompt: section.dataset.prompt || null,
                text: document.getElementById('question-text').textContent,
                buttons: Array.from(document.querySelectorAll('#buttons button'),
                                    b => b.textContent)};""")


def wait_for_question(driver, prompt: str, timeout: float = 20.0) -> dict:
    WebDriverWait(driver, timeout, poll_frequency=0.05).until(
        lambda d: shown(d)["mode"] == "question" and shown(d)["prompt"] == prompt)
    return shown(driver)


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_run(folder, scenario, port: int, data, trace, env) -> subprocess.Popen:
    """A real-time survey run serving the page on `port` (in its own session)."""
    return subprocess.Popen([sys.executable, "-m", "applications.cli", "run", str(folder),
                             "--gui", f"127.0.0.1:{port}", "--scenario", str(scenario),
                             "--duration", RUN_SECONDS, "--data", str(data),
                             "--trace", str(trace), "--quiet"],
                            stdout=subprocess.PIPE, text=True, env=env, start_new_session=True)


def page_url(run: subprocess.Popen) -> str:
    """The URL the run printed at start."""
    for line in run.stdout:
        found = re.search(r"tablet page at (http://127\.0\.0\.1:\d+/\?token=\S+)", line)
        if found:
            return found.group(1)
    raise AssertionError("the run did not print the tablet page's URL")


def stop(run: subprocess.Popen) -> None:
    if run.poll() is None:
        os.killpg(run.pid, signal.SIGKILL)      # its own session: espeak-ng children go too
        run.wait()
    run.stdout.close()


@pytest.mark.slow
def test_a_person_answers_the_whole_survey_on_the_page(quick_survey, tmp_path):
    folder, scenario = quick_survey
    env = {**os.environ, "INTERBOT_TABLET_SECRET": str(tmp_path / "tablet-secret")}
    port = free_port()
    runs = []
    try:
        first = start_run(folder, scenario, port, tmp_path / "data1", tmp_path / "run1.jsonl",
                          env)
        runs.append(first)
        with chromium() as driver:                    # starts while the run starts
            url = page_url(first)
            driver.get(url.split("token=")[0] + "token=wrong")
            assert "403" in driver.find_element(By.TAG_NAME, "body").text
            driver.get(url)
            first_question = wait_for_question(driver, "q1")
            assert first_question["text"] == "Do you like working on this floor?"
            assert first_question["buttons"] == ["yes", "no"]
            png = driver.get_screenshot_as_png()
            picture = Image.open(io.BytesIO(png)).convert("L")
            assert picture.size[0] >= 800 and len(png) > 10_000
            assert len(picture.getcolors(256)) > 20     # text and buttons, not a blank page

            main_tab = driver.current_window_handle
            driver.switch_to.new_window("tab")
            driver.get(url)
            assert wait_for_question(driver, "q1") == first_question   # a second tablet
            driver.close()
            driver.switch_to.window(main_tab)
            driver.refresh()                                      # a reconnecting tablet
            assert wait_for_question(driver, "q1") == first_question
            driver.find_element(By.CSS_SELECTOR, '#buttons button[data-value="yes"]').click()
            wait_for_question(driver, "q2")

            stop(first)                                           # kill -9 mid-question
            WebDriverWait(driver, 5, poll_frequency=0.05).until(
                lambda d: shown(d)["mode"] == "offline")
            assert not driver.find_element(By.ID, "question-text").is_displayed()
            assert "The robot is not running" in driver.find_element(By.ID, "offline").text

            second = start_run(folder, scenario, port, tmp_path / "data2",
                               tmp_path / "run2.jsonl", env)
            runs.append(second)
            new_url = page_url(second)
            assert new_url.split("token=")[1] != url.split("token=")[1]
            for prompt, answer in ANSWERS.items():              # the same page, its old URL
                question = wait_for_question(driver, prompt)
                assert answer in question["buttons"]
                driver.find_element(By.CSS_SELECTOR,
                                    f'#buttons button[data-value="{answer}"]').click()
            WebDriverWait(driver, 20, poll_frequency=0.05).until(
                lambda d: shown(d)["mode"] == "idle")
        second.send_signal(signal.SIGINT)                         # done: no need to wait it out
        assert second.wait(timeout=30) == 128 + signal.SIGINT
    finally:
        for run in runs:
            stop(run)
    with sqlite3.connect(tmp_path / "data2" / "survey.sqlite") as db:
        stored = dict(db.execute("SELECT question, answer FROM answers ORDER BY id").fetchall())
    assert stored == ANSWERS
    answers = [e for e in read_trace(tmp_path / "run2.jsonl") if e["kind"] == "answer"]
    assert [(e["question"], e["answer"], e["source"]) for e in answers] == [
        (q, a, "touch") for q, a in ANSWERS.items()]
