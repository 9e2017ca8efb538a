"""The live inspector: its server (token, endpoints, pause and step) and its page in headless
Chromium during a run."""
from __future__ import annotations

import json
import shutil
import socket
import subprocess
import threading
import time
import urllib.error
import urllib.request

import lxml.html
import pytest

from applications.exceptions import ApplicationError
from applications.graph.loader import find_application, load_application
from applications.inspect.server import Inspector, parse_address
from applications.runtime import Run
from behaviors.robot import open_robot

SURVEY = find_application("survey")
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync"]


def get(url: str, method: str = "GET") -> tuple[int, bytes]:
    request = urllib.request.Request(url, method=method)
    try:
        with urllib.request.urlopen(request, timeout=30) as reply:
            return reply.status, reply.read()
    except urllib.error.HTTPError as error:
        return error.code, error.read()


class Browser:
    """Headless Chromium driven through chromedriver's WebDriver protocol (Debian's `chromium`
    and `chromium-driver`), with the few calls these tests need."""

    def __init__(self, profile_dir) -> None:
        chromium = shutil.which("chromium") or shutil.which("chromium-browser")
        driver = shutil.which("chromedriver")
        assert chromium and driver, "needs headless Chromium: apt-get install chromium chromium-driver"
        with socket.socket() as probe:
            probe.bind(("127.0.0.1", 0))
            port = probe.getsockname()[1]
        self.driver = subprocess.Popen([driver, f"--port={port}"], stdout=subprocess.DEVNULL,
                                       stderr=subprocess.DEVNULL)
        self.base = f"http://127.0.0.1:{port}"
        deadline = time.monotonic() + 60
        while True:
            try:
                if self._call("GET", "/status")["ready"]:
                    break
            except OSError:
                pass
            assert time.monotonic() < deadline, "chromedriver did not start"
            time.sleep(0.1)
        options = {"binary": chromium, "args": [*CHROMIUM_FLAGS, f"--user-data-dir={profile_dir}"]}
        reply = self._call("POST", "/session", {"capabilities": {"alwaysMatch": {
            "browserName": "chrome", "goog:chromeOptions": options}}})
        self.session = f"/session/{reply['sessionId']}"

    def _call(self, method: str, path: str, body: dict | None = None):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(self.base + path, data=data, method=method,
                                         headers={"Content-Type": "application/json"})
        with urllib.request.urlopen(request, timeout=120) as reply:
            return json.loads(reply.read())["value"]

    def open(self, url: str) -> None:
        self._call("POST", self.session + "/url", {"url": url})

    def script(self, code: str):
        return self._call("POST", self.session + "/execute/sync", {"script": code, "args": []})

    def wait_for(self, code: str, expected, timeout: float = 60.0):
        deadline = time.monotonic() + timeout
        while (value := self.script(code)) != expected and time.monotonic() < deadline:
            time.sleep(0.1)
        return value

    def close(self) -> None:
        try:
            self._call("DELETE", self.session)
        except Exception:
            pass
        finally:
            self.driver.terminate()
            self.driver.wait(30)


def flatten(node: dict) -> list[tuple[str, str]]:
    out = [(node["name"], node["status"])]
    for child in node.get("children", ()):
        out += flatten(child)
    return out


def test_parse_address():
    assert parse_address("8765") == ("127.0.0.1", 8765)
    assert parse_address("0.0.0.0:0") == ("0.0.0.0", 0)
    assert parse_address("[::1]:9000") == ("::1", 9000)
    with pytest.raises(ApplicationError, match="give \\[HOST:\\]PORT"):
        parse_address("localhost:http")
    with pytest.raises(ApplicationError, match="outside 0..65535"):
        parse_address("70000")


def test_the_server_wants_its_token_and_serves_graph_and_newest_snapshot():
    app = load_application(SURVEY)
    inspector = Inspector(app, address="0", robot="horos", page_rate=float("inf")).start()
    try:
        base = f"http://127.0.0.1:{inspector.port}"
        assert inspector.url.startswith(base) and len(inspector.token) >= 20
        assert get(base + "/")[0] == 403
        assert get(base + "/api/static?token=wrong")[0] == 403
        status, page = get(inspector.url)
        assert status == 200 and b"<canvas id=\"top\"" in page and b"src=" not in page
        status, body = get(f"{base}/api/static?token={inspector.token}")
        static = json.loads(body)
        assert status == 200 and static["app"] == "survey" and not static["controls"]
        titles = lxml.html.fromstring(static["graph"]).xpath("//g[@class='node']/title/text()")
        assert set(titles) - {"__start"} == set(app.states)
        inspector({"tick": 0, "t": 0.0, "state": "Wait", "robot": {
            "skills": {"hardware": {"inputs": [["now", 0.0]], "base": None}}}})
        inspector({"tick": 1, "t": 0.1, "state": "Wait", "robot": {
            "skills": {"hardware": {"inputs": [["now", 0.1]], "base": None}}}})
        status, body = get(f"{base}/api/snapshot?after=0&token={inspector.token}")
        data = json.loads(body)
        assert data["seq"] == 2 and data["snapshot"]["tick"] == 1     # only the newest
        assert "inputs" not in data["snapshot"]["robot"]["skills"]["hardware"]
        assert get(f"{base}/api/control?action=pause&token={inspector.token}", "POST")[0] == 409
    finally:
        inspector.close()


def test_pause_and_step_hold_the_loop_one_tick_at_a_time():
    app = load_application(SURVEY)
    inspector = Inspector(app, address="0", controls=True).start()
    ticks: list[int] = []
    try:
        inspector.control("pause")

        def loop():
            for tick in range(5):
                inspector({"tick": tick, "robot": {}})
                ticks.append(tick)
        thread = threading.Thread(target=loop)
        thread.start()
        thread.join(0.5)
        assert ticks == []                       # paused: the first tick waits
        status, body = get(f"http://127.0.0.1:{inspector.port}/api/control?action=step"
                           f"&token={inspector.token}", "POST")
        assert status == 200 and json.loads(body)["paused"]
        thread.join(0.5)
        assert ticks == [0]                      # one step: one tick, then held again
        inspector.control("resume")
        thread.join(30)
        assert ticks == [0, 1, 2, 3, 4]
    finally:
        inspector.close()


def test_the_page_shows_the_state_and_node_statuses_during_a_run(tmp_path):
    """A run is held inside the Interaction state while headless Chromium loads the page;
    the page must show that tick's state, behavior, tree statuses and percepts."""
    app = load_application(SURVEY)
    robot = open_robot("horos", scenario=SURVEY / "scenarios" / "complete.toml", fast=True)
    inspector = Inspector(app, address="0", robot="horos", map_=robot.top_view()).start()
    held, release, seen = threading.Event(), threading.Event(), {}

    def hold(snapshot):
        if (not held.is_set() and snapshot["state"] == "Interaction"
                and snapshot["time_in_state"] >= 1.0 and inspector._latest is snapshot):
            seen["snapshot"] = snapshot
            held.set()
            release.wait(300)

    run = Run(app, robot, echo=None, duration=60, observers=[inspector, hold])
    thread = threading.Thread(target=run.run)
    thread.start()
    browser = None
    try:
        assert held.wait(120), "the run never reached Interaction"
        browser = Browser(tmp_path / "chromium")
        browser.open(inspector.url)
        tick = str(seen["snapshot"]["tick"])
        assert browser.wait_for("return document.body.dataset.tick || ''", tick) == tick
        dom = lxml.html.fromstring(browser.script("return document.documentElement.outerHTML"))
    finally:
        if browser is not None:
            browser.close()
        release.set()
        thread.join(120)
        inspector.close()
        robot.close()
    snapshot = seen["snapshot"]
    assert dom.get_element_by_id("state").text_content() == "Interaction"
    assert dom.get_element_by_id("tick").text_content() == str(snapshot["tick"])
    assert dom.get_element_by_id("behavior").text_content().startswith("Survey (")
    assert dom.get_element_by_id("link").text_content() == "live"
    shown = [(li.get("data-name"), li.get("data-status"))
             for li in dom.get_element_by_id("tree").iter("li")]
    assert shown == flatten(snapshot["robot"]["tree"])
    assert {status for _, status in shown} >= {"RUNNING"}
    current = dom.xpath("//div[@id='graph']//g[contains(@class, 'current')]/title/text()")
    assert current == ["Interaction"]
    fired = dom.xpath("//div[@id='graph']//g[contains(@class, 'fired')]/title/text()")
    assert [t.replace("&#45;", "-") for t in fired] == ["CreateAttention->Interaction"]
    assert "user.distance" in dom.get_element_by_id("fired").text_content()
    rows = {tr.get("data-name"): [td.text_content() for td in tr.iter("td")]
            for tr in dom.get_element_by_id("percepts").iter("tr") if tr.get("data-name")}
    distance = snapshot["robot"]["percepts"]["user.distance"]["value"]
    assert rows["user.distance"][1] == f"{distance:.2f}"
    assert rows["user.present"][1] == "true"
    skills = {tr.get("data-name") for tr in dom.get_element_by_id("skills").iter("tr")}
    assert {"questionnaire", "perception", "motion"} <= skills


def test_without_graphviz_the_graph_is_drawn_by_our_own_layout():
    from applications.inspect.graph_svg import own_svg

    app = load_application(SURVEY)
    svg = lxml.html.fromstring(own_svg(app))
    assert set(svg.xpath("//g[@class='node']/title/text()")) == set(app.states)
    edges = svg.xpath("//g[@class='edge']/title/text()")
    expected = {f"{state.name}->{t.target}" for state in app.states.values()
                for t in state.transitions}
    assert set(edges) == expected and len(edges) == len(expected)
    assert "user.distance &lt; 0.75m" in own_svg(app)
