// The tablet page: render every screen the robot pushes; send a press at the first touch.
"use strict";
(function () {
  const token = new URLSearchParams(location.search).get("token") || "";
  const main = document.getElementById("screen");
  const link = document.getElementById("link");
  let socket = null;
  let retry = 250;              // ms before reconnecting; doubles up to 4 s
  let current = null;

  function text(id, value) { document.getElementById(id).textContent = value || ""; }

  let shownKey = "";            // what the view was last built for (the caption aside)

  function render(screen, rebuild) {
    current = screen;
    main.dataset.mode = screen.mode;
    main.dataset.version = screen.v;
    text("caption", screen.caption);
    // A new caption alone leaves the buttons as they are, so a touch under way is not lost.
    const key = JSON.stringify([screen.mode, screen.prompt, screen.text, screen.buttons,
                                screen.typed, screen.picture]);
    if (key === shownKey && !rebuild) { return; }
    shownKey = key;
    if (screen.mode === "question") {
      text("question-text", screen.text);
      const box = document.getElementById("buttons");
      box.replaceChildren(...screen.buttons.map(function (label) {
        const button = document.createElement("button");
        button.className = "answer";
        button.type = "button";
        button.textContent = label;
        button.dataset.value = label;
        button.addEventListener("pointerdown", function () { press(button, label); });
        button.addEventListener("click", function () { press(button, label); });
        return button;
      }));
      const section = document.getElementById("question");
      section.classList.toggle("typed", !!screen.typed);
      section.dataset.prompt = screen.prompt;
      document.getElementById("typed-text").value = "";
    } else if (screen.mode === "info") {
      text("info-text", screen.text);
      const img = document.getElementById("info-picture");
      if (screen.picture) { img.src = screen.picture + "?token=" + encodeURIComponent(token); }
      else { img.removeAttribute("src"); }
    }
  }

  function press(button, value) {
    if (!current || current.mode !== "question" || button.disabled) { return; }
    // Feedback at once, before the robot answers: the touched button lights up, the rest dim.
    document.querySelectorAll("button.answer").forEach(function (b) { b.disabled = true; });
    if (button) { button.classList.add("pressed"); }
    send({ type: "press", prompt: current.prompt, value: value });
  }

  function send(message) {
    if (socket && socket.readyState === WebSocket.OPEN) { socket.send(JSON.stringify(message)); }
  }

  function received(event) {
    const message = JSON.parse(event.data);
    if (message.type === "screen") {
      render(message.screen);
    } else if (message.type === "accepted") {
      document.querySelectorAll("button.answer.pressed").forEach(function (b) {
        b.classList.add("sent");
      });
    } else if (message.type === "refused" && current) {
      render(current, true);    // undo the feedback: the press did not count
    }
  }

  function connect() {
    const scheme = location.protocol === "https:" ? "wss://" : "ws://";
    socket = new WebSocket(scheme + location.host + "/ws?token=" + encodeURIComponent(token));
    socket.addEventListener("open", function () { retry = 250; link.classList.remove("offline"); });
    socket.addEventListener("message", received);
    socket.addEventListener("close", function (event) {
      link.classList.add("offline");
      link.textContent = event.code === 4403 ? "not allowed: " + event.reason
                                             : "connection lost, reconnecting…";
      if (event.code !== 4403) { setTimeout(connect, retry); retry = Math.min(retry * 2, 4000); }
    });
  }

  document.getElementById("typed").addEventListener("submit", function (event) {
    event.preventDefault();
    const value = document.getElementById("typed-text").value.trim();
    if (value) { press(document.getElementById("typed-send"), value); }
  });
  connect();
})();
