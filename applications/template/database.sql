-- The database of {name}. It runs at every start: keep it safe to run twice
-- (CREATE TABLE IF NOT EXISTS, INSERT OR REPLACE). Answers are written here as they are given.
CREATE TABLE IF NOT EXISTS answers (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,   -- one run of `interbot run`
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,   -- one person within the run
    question    TEXT    NOT NULL,
    answer      TEXT    NOT NULL,
    robot_time  REAL    NOT NULL,   -- s since the run started
    wall_time   REAL    NOT NULL    -- Unix time
);
