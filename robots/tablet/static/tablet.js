// The tablet page: render every screen the robot pushes; send a press at the first touch; say
// plainly when the robot is gone, and find it again (a restarted robot knows a paired tablet by
// its pass cookie, though the token in this page's address is old).
"use strict";
(function () {
  const params = new URLSearchParams(location.search);
  const token = params.get("token") || "";
  const tabletName = (params.get("name") || "").slice(0, 40);   // told to the other tablets
  const PRESS_TIMEOUT = 3000;   // ms without a reply before a press is given up
  const RETRY_FIRST = 250;      // ms before looking for the robot again; doubles …
  const RETRY_MOST = 2000;      // … up to this
  const main = document.getElementById("screen");
  const typedSend = document.getElementById("typed-send");
  const typedText = document.getElementById("typed-text");
  const me = pageId();
  let socket = null;
  let retry = RETRY_FIRST;
  let current = null;           // the screen shown (null while the robot is away)
  let shownKey = "";            // what the view was last built for (caption and answer aside)
  let pending = null;           // the press sent and not yet accepted or refused

  function text(id, value) { document.getElementById(id).textContent = value || ""; }
  function notice(value) { text("notice", value); }
  function where(answered) {
    return answered.who ? "on the tablet “" + answered.who + "”" : "on another tablet";
  }

  function pageId() {           // this tab's id, kept over a reload, to tell "you" from others
    try {
      let id = sessionStorage.getItem("interbot-page");
      if (!id) {
        id = Math.random().toString(36).slice(2, 12);
        sessionStorage.setItem("interbot-page", id);
      }
      return id;
    } catch (error) { return Math.random().toString(36).slice(2, 12); }
  }

  function answers() { return document.querySelectorAll("button.answer"); }

  function render(screen) {
    current = screen;
    main.dataset.mode = screen.mode;
    main.dataset.version = screen.v;
    delete main.dataset.why;
    text("caption", screen.caption);
    // A new caption alone leaves the view as it is, so a touch under way is not lost.
    const key = JSON.stringify([screen.mode, screen.prompt, screen.ask, screen.text,
                                screen.buttons, screen.typed, screen.picture]);
    if (key !== shownKey) {
      shownKey = key;
      build(screen);
    }
    if (screen.mode === "question") { showAnswered(screen.answered); }
  }

  function build(screen) {
    settled();
    notice("");
    if (screen.mode === "question") {
      text("question-text", screen.text);
      const box = document.getElementById("buttons");
      box.replaceChildren(...screen.buttons.map(answerButton));
      box.toggleAttribute("data-few", screen.buttons.length <= 4);
      box.scrollTop = 0;
      const section = document.getElementById("question");
      section.classList.toggle("typed", !!screen.typed);
      section.dataset.prompt = screen.prompt;
      typedText.value = "";
      typedSend.classList.remove("pressed", "sent");
      enable(true);
    } else if (screen.mode === "info") {
      text("info-text", screen.text);
      const img = document.getElementById("info-picture");
      if (screen.picture) { img.src = screen.picture + "?token=" + encodeURIComponent(token); }
      else { img.removeAttribute("src"); }
    }
  }

  function answerButton(label) {
    const button = document.createElement("button");
    button.className = "answer";
    button.type = "button";
    button.textContent = label;
    button.dataset.value = label;
    button.addEventListener("pointerdown", function () { press(button, label); });
    button.addEventListener("click", function () { press(button, label); });
    return button;
  }

  function enable(on) {
    answers().forEach(function (b) { b.disabled = !on; });
    typedText.disabled = !on;
  }

  // The question's answer, once given on any page: shown on every page, nothing more to press.
  function showAnswered(answered) {
    if (!answered) {
      if (!pending) { enable(true); }
      return;
    }
    enable(false);
    const match = Array.from(document.querySelectorAll("#buttons button"))
      .find(function (b) { return b.dataset.value === answered.value; });
    (match || typedSend).classList.add("sent");
    if (answered.by !== me) {
      notice("Answered " + where(answered) + ": “" + answered.value + "”");
    }
  }

  function press(button, value) {
    if (!current || current.mode !== "question" || current.answered || pending ||
        button.disabled) { return; }
    if (!socket || socket.readyState !== WebSocket.OPEN) { return; }
    // Feedback at once, before the robot answers: the touched button lights up, the rest dim.
    enable(false);
    button.classList.add("pressed");
    pending = setTimeout(gaveUp, PRESS_TIMEOUT);
    socket.send(JSON.stringify({ type: "press", prompt: current.prompt, value: value, page: me,
                                 name: tabletName }));
  }

  function settled() {          // the press under way, if any, has its answer: stop waiting
    if (pending) { clearTimeout(pending); }
    pending = null;
  }

  function undoPress() {
    settled();
    answers().forEach(function (b) { b.classList.remove("pressed"); });
    if (current && current.mode === "question") { showAnswered(current.answered); }
  }

  function gaveUp() {           // no reply: the robot hangs, or the connection is dead
    pending = null;
    undoPress();
    const dead = socket;
    lost();
    if (dead) { dead.close(); }
  }

  function received(event) {
    if (event.target !== socket) { return; }     // a connection given up: not listened to
    const message = JSON.parse(event.data);
    if (message.type === "screen") {
      render(message.screen);
    } else if (message.type === "accepted") {
      settled();
      answers().forEach(function (b) {
        if (b.classList.contains("pressed")) { b.classList.add("sent"); }
      });
    } else if (message.type === "refused") {
      undoPress();
      const answered = message.answered;
      if (answered && answered.by !== me) {
        notice("Already answered " + where(answered) + ": “" + answered.value + "”");
      } else if (!answered && current && current.prompt !== message.prompt) {
        notice("Too late: the robot has moved on.");
      }
    }
  }

  // --- the robot, gone and back -------------------------------------------------------------
  function away(why) {
    settled();
    current = null;
    shownKey = "";
    main.dataset.mode = "offline";
    main.dataset.why = why;
    text("caption", "");
    notice("");
  }

  function lost() {
    socket = null;
    away("gone");
    setTimeout(findRobot, retry);
    retry = Math.min(retry * 2, RETRY_MOST);    // back to the first once a connection opens
  }

  function findRobot() {        // is it back, and does it know this tablet?
    const again = function (why) {
      away(why);
      retry = Math.min(retry * 2, RETRY_MOST);
      setTimeout(findRobot, retry);
    };
    const options = { cache: "no-store", credentials: "same-origin" };
    if (window.AbortSignal && AbortSignal.timeout) { options.signal = AbortSignal.timeout(3000); }
    fetch("/hello?token=" + encodeURIComponent(token), options)
      .then(function (response) {
        if (response.ok) { connect(); }
        else { again(response.status === 403 ? "new-key" : "gone"); }
      })
      .catch(function () { again("gone"); });
  }

  function connect() {
    const scheme = location.protocol === "https:" ? "wss://" : "ws://";
    const ws = new WebSocket(scheme + location.host + "/ws?token=" + encodeURIComponent(token));
    socket = ws;
    ws.addEventListener("open", function () { retry = RETRY_FIRST; });
    ws.addEventListener("message", received);
    ws.addEventListener("close", function () { if (socket === ws) { lost(); } });
  }

  document.getElementById("typed").addEventListener("submit", function (event) {
    event.preventDefault();
    const value = typedText.value.trim();
    if (value) { press(typedSend, value); }
  });
  connect();
})();
