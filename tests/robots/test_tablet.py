"""The tablet page's server, driven as a browser would be (HTTP and a WebSocket over 127.0.0.1):
who may connect, what every page sees, and which presses reach the robot."""
from __future__ import annotations

import asyncio
import json
import threading
import urllib.error
import urllib.request

import pytest
import websockets

from robots.exceptions import RobotError
from robots.tablet import WebTouchScreen, parse_address
from robots.tablet.device import is_local
from robots.tablet.pairing import default_secret_file, load_secret
from robots.tablet.screen import ScreenContent


@pytest.fixture
def tablet():
    screen = WebTouchScreen("127.0.0.1", 0)
    yield screen
    screen.close()


def origin(screen) -> str:
    return screen.url.split("/?")[0]


def socket_url(screen, token: str | None = None) -> str:
    url = screen.url.replace("http://", "ws://").replace("/?", "/ws?")
    return url if token is None else url.split("token=")[0] + f"token={token}"


async def next_screen(ws) -> dict:
    while True:
        message = json.loads(await asyncio.wait_for(ws.recv(), 10))
        if message["type"] == "screen":
            return message["screen"]


async def next_reply(ws) -> dict:
    """The next message that is not a screen (the reply to what the page sent)."""
    while True:
        message = json.loads(await asyncio.wait_for(ws.recv(), 10))
        if message["type"] != "screen":
            return message


async def press(ws, prompt: str, value: str, page: str = "") -> dict:
    await ws.send(json.dumps({"type": "press", "prompt": prompt, "value": value, "page": page}))
    return await next_reply(ws)


def test_the_page_needs_the_token(tablet):
    with urllib.request.urlopen(tablet.url) as page:
        html = page.read().decode()
        assert page.headers["Referrer-Policy"] == "no-referrer"
    assert "/static/tablet.js" in html and "http" not in html.replace("http-equiv", "")
    bad = tablet.url.split("token=")[0] + "token=guess"
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(bad)
    assert refused.value.code == 403


def test_a_websocket_needs_the_token_and_the_page_origin(tablet):
    async def attempt(url, from_origin):
        async with websockets.connect(url, origin=from_origin) as ws:
            return await next_screen(ws)

    assert asyncio.run(attempt(socket_url(tablet), origin(tablet)))["mode"] == "idle"
    for url, from_origin in ((socket_url(tablet, "guess"), origin(tablet)),
                             (socket_url(tablet), "http://evil.example"),
                             (socket_url(tablet), None)):
        with pytest.raises(websockets.exceptions.InvalidStatus) as refused:
            asyncio.run(attempt(url, from_origin))
        assert refused.value.response.status_code == 403
    assert tablet.take_press() is None


def test_two_pages_see_the_same_screen_and_a_reconnecting_page_gets_it_back(tablet):
    async def scenario():
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as one, \
                   websockets.connect(socket_url(tablet), origin=origin(tablet)) as two:
            assert (await next_screen(one))["mode"] == (await next_screen(two))["mode"] == "idle"
            tablet.show("q1", "Coffee?", ("yes", "no"))
            first, second = await next_screen(one), await next_screen(two)
            assert first == second
            assert first["text"] == "Coffee?" and first["buttons"] == ["yes", "no"]
        tablet.caption("Please answer on my screen.")
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as again:
            back = await next_screen(again)
        return first, back

    first, back = asyncio.run(scenario())
    assert back["prompt"] == "q1" and back["caption"] == "Please answer on my screen."
    assert back["v"] > first["v"]


def test_presses_for_the_shown_question_are_queued_others_refused(tablet):
    tablet.show("q1", "Coffee?", ("yes", "no"))

    async def presses():
        replies = []
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as ws:
            await next_screen(ws)
            for prompt, value in (("q1", "maybe"), ("q0", "yes"), ("q1", "no")):
                replies.append((await press(ws, prompt, value))["type"])
            await ws.send("not json")
            replies.append((await next_reply(ws))["type"])
            await ws.send(b"\x00\x01")
            replies.append((await next_reply(ws))["type"])
        return replies

    assert asyncio.run(presses()) == ["refused", "refused", "accepted", "refused", "refused"]
    assert tablet.take_press() == ("q1", "no")
    assert tablet.take_press() is None
    assert tablet.take_press_from() is None


def test_pictures_go_by_url_never_inside_the_json(tablet, tmp_path):
    picture = tmp_path / "map.png"
    picture.write_bytes(b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 8)
    tablet.display("Room N2 is down the hall.", str(picture))
    snapshot = tablet.content.snapshot()
    assert snapshot["mode"] == "info" and snapshot["picture"] == "/picture/1"
    assert len(json.dumps(snapshot)) < 200
    base = origin(tablet)
    with urllib.request.urlopen(f"{base}/picture/1?token={tablet.guard.token}") as response:
        assert response.read() == picture.read_bytes()
    with pytest.raises(urllib.error.HTTPError) as refused:
        urllib.request.urlopen(f"{base}/picture/1?token=guess")
    assert refused.value.code == 403


def test_typed_answers_are_accepted_only_where_the_question_takes_text():
    content = ScreenContent()
    content.show("name", "Your name?", ("skip",), typed=False)
    assert "not one of the answers" in content.press("name", "Ada")
    content.show("name", "Your name?", ("skip",), typed=True)
    assert "characters" in content.press("name", "x" * 500)
    assert "characters" in content.press("name", "   ")
    assert content.press("name", "  Ada  ") is None
    assert content.take_press() == ("name", "Ada")


def test_showing_the_same_screen_again_pushes_nothing():
    content, pushed = ScreenContent(), []
    content.listeners.append(lambda: pushed.append(content.version))
    content.show("q1", "Coffee?", ("yes", "no"), False)
    content.show("q1", "Coffee?", ("yes", "no"), False)
    content.clear()
    assert pushed == [1, 2]


def test_of_presses_racing_from_many_threads_exactly_one_counts():
    content = ScreenContent()
    content.show("q", "Pick", tuple(str(i) for i in range(8)), False)
    refusals = []
    threads = [threading.Thread(target=lambda i=i: refusals.extend(
                   content.press("q", str(i), f"page{i}") for _ in range(50)))
               for i in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    taken = []
    while (press := content.take_press()) is not None:
        taken.append(press)
    assert len(taken) == 1 and refusals.count(None) == 1
    winner = content.snapshot()["answered"]
    assert taken == [("q", winner["value"])] and winner["by"] == f"page{winner['value']}"
    assert content.answered("q") == winner
    assert set(refusals) - {None} == {"that question has already been answered"}


def test_the_same_question_shown_again_after_its_answer_is_asked_anew():
    content = ScreenContent()
    content.show("more", "Another one?", ("yes", "no"), False)
    first = content.snapshot()
    content.show("more", "Another one?", ("yes", "no"), False)   # still waiting: no change
    assert content.snapshot() == first
    assert content.press("more", "yes", "a") is None
    assert content.snapshot()["answered"] == {"value": "yes", "by": "a", "who": ""}
    content.show("more", "Another one?", ("yes", "no"), False)   # the loop asks again
    again = content.snapshot()
    assert "answered" not in again and again["ask"] == first["ask"] + 1
    assert content.press("more", "no", "b") is None
    assert [content.take_press(), content.take_press()] == [("more", "yes"), ("more", "no")]


def test_addresses():
    assert parse_address("8080") == ("127.0.0.1", 8080)
    assert parse_address("0.0.0.0:0") == ("0.0.0.0", 0)
    assert parse_address("[::1]:8080") == ("::1", 8080)
    for bad in ("http", "host:99999", ""):
        with pytest.raises(RobotError, match=r"\[HOST:\]PORT"):
            parse_address(bad)


def test_a_port_in_use_is_a_clear_error(tablet):
    with pytest.raises(RobotError, match="cannot listen"):
        WebTouchScreen("127.0.0.1", tablet.server.port)


def test_two_pages_the_late_one_is_told_who_answered(tablet):
    tablet.show("q1", "Coffee?", ("yes", "no"))

    async def race():
        async with websockets.connect(socket_url(tablet), origin=origin(tablet)) as one, \
                   websockets.connect(socket_url(tablet), origin=origin(tablet)) as two:
            await next_screen(one), await next_screen(two)
            await one.send(json.dumps({"type": "press", "prompt": "q1", "value": "yes",
                                       "page": "tablet-one", "name": "Entrance"}))
            won = await next_reply(one)
            seen_by_two = await next_screen(two)        # the answer reaches every page at once
            lost = await press(two, "q1", "no", "tablet-two")
            tablet.show("q2", "Tea?", ("yes", "no"))
            late = await press(two, "q1", "no", "tablet-two")  # after the robot moved on
            return won, seen_by_two, lost, late

    won, seen_by_two, lost, late = asyncio.run(race())
    assert won["type"] == "accepted"
    answer = {"value": "yes", "by": "tablet-one", "who": "Entrance"}
    assert seen_by_two["answered"] == answer
    assert lost["type"] == late["type"] == "refused"
    assert lost["answered"] == late["answered"] == answer
    assert tablet.take_press() == ("q1", "yes") and tablet.take_press() is None


def hello(screen, token: str | None = None, cookie: str | None = None) -> int:
    request = urllib.request.Request(
        f"{origin(screen)}/hello?token={token or screen.guard.token}",
        headers={"Cookie": cookie} if cookie else {})
    try:
        with urllib.request.urlopen(request) as response:
            return response.status
    except urllib.error.HTTPError as refused:
        return refused.code


def test_a_paired_tablet_is_let_in_by_the_next_run_with_its_new_token(tmp_path):
    secret = tmp_path / "state" / "tablet-secret"
    first = WebTouchScreen("127.0.0.1", 0, secret_file=secret)
    try:
        with urllib.request.urlopen(first.url) as page:
            cookie = page.headers["Set-Cookie"]
        assert "HttpOnly" in cookie and "SameSite=strict" in cookie
        assert cookie.startswith(f"interbot_pass_{first.server.port}=")
        port, old_token = first.server.port, first.guard.token
    finally:
        first.close()
    assert secret.stat().st_mode & 0o777 == 0o600
    pass_cookie = cookie.split(";")[0]
    again = WebTouchScreen("127.0.0.1", port, secret_file=secret)       # a restart
    stranger = WebTouchScreen("127.0.0.1", 0, secret_file=tmp_path / "other-secret")
    try:
        assert again.guard.token != old_token
        assert hello(again, token=old_token) == 403                  # the old token alone
        assert hello(again, token=old_token, cookie=pass_cookie) == 204
        assert hello(stranger, token="old", cookie=pass_cookie.replace(
            str(port), str(stranger.server.port))) == 403            # another robot's pass

        async def reconnect():
            async with websockets.connect(socket_url(again, old_token), origin=origin(again),
                                          additional_headers={"Cookie": pass_cookie}) as ws:
                return await next_screen(ws)

        again.show("q1", "Coffee?", ("yes", "no"))
        assert asyncio.run(reconnect())["prompt"] == "q1"
    finally:
        again.close()
        stranger.close()


def test_without_pairing_no_cookie_and_the_token_alone_counts(tablet):
    with urllib.request.urlopen(tablet.url) as page:
        assert page.headers["Set-Cookie"] is None
    assert hello(tablet) == 204 and hello(tablet, token="guess") == 403


def test_a_page_open_to_the_network_is_a_one_line_warning(tmp_path):
    local = WebTouchScreen("127.0.0.1", 0)
    wide = WebTouchScreen("0.0.0.0", 0)
    unpaired = WebTouchScreen("127.0.0.1", 0, secret_file=tmp_path)   # a folder: unreadable
    try:
        assert local.notes == []
        assert len(wide.notes) == 1 and "\n" not in wide.notes[0]
        assert wide.notes[0].startswith("warning: the tablet page listens on 0.0.0.0:")
        assert len(unpaired.notes) == 1 and "cannot be paired" in unpaired.notes[0]
    finally:
        for screen in (local, wide, unpaired):
            screen.close()
    assert is_local("127.0.0.1") and is_local("::1") and is_local("localhost")
    assert not is_local("0.0.0.0") and not is_local("192.168.5.1") and not is_local("robot")


def test_the_pairing_secret_is_made_once_and_kept(tmp_path, monkeypatch):
    monkeypatch.setenv("INTERBOT_TABLET_SECRET", str(tmp_path / "s"))
    assert default_secret_file() == tmp_path / "s"
    monkeypatch.delenv("INTERBOT_TABLET_SECRET")
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "xdg"))
    path = default_secret_file()
    assert path == tmp_path / "xdg" / "interbot" / "tablet-secret"
    made = load_secret(path)
    assert len(made) == 32 and load_secret(path) == made
    path.write_bytes(b"short")
    with pytest.raises(ValueError, match="at least 16 bytes"):
        load_secret(path)
