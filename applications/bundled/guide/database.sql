-- The office guide's database: the building's rooms and staff (edit these to your building),
-- the visitors' choices and the log of guide runs (the robot writes those two).
-- This file runs at every start: keep it safe to run twice (IF NOT EXISTS, OR REPLACE).
CREATE TABLE IF NOT EXISTS answers (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,   -- one run of `interbot run`
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,   -- one visitor within the run
    question    TEXT    NOT NULL,
    answer      TEXT    NOT NULL,
    robot_time  REAL    NOT NULL,   -- s since the run started
    wall_time   REAL    NOT NULL    -- Unix time
);

-- One row per guide run, written by the robot when the run ends: where to, how it ended
-- ('arrived', 'user lost', 'navigation failed', 'cancelled'), why, and how long it took.
CREATE TABLE IF NOT EXISTS guide_runs (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,
    robot       TEXT    NOT NULL,
    place       TEXT    NOT NULL,   -- the place of the map the robot led to
    outcome     TEXT    NOT NULL,
    reason      TEXT    NOT NULL,
    duration    REAL    NOT NULL,   -- s from leading off to the end
    robot_time  REAL    NOT NULL,
    wall_time   REAL    NOT NULL
);

-- Rooms a visitor may ask for: `name` is recorded, `label` is the button, `place` is the place
-- of the robot's map the robot leads to (its map's places: interbot's docs/navigation.md).
-- A column X_de holds column X in German (the application's second language, dialog.xml).
CREATE TABLE IF NOT EXISTS rooms (
    name     TEXT PRIMARY KEY,
    label    TEXT NOT NULL,
    place    TEXT NOT NULL,
    label_de TEXT NOT NULL DEFAULT ''
);
INSERT OR REPLACE INTO rooms (name, label, place, label_de) VALUES
    ('N1', 'Room N1', 'room_n1', 'Raum N1'),
    ('N2', 'Room N2', 'room_n2', 'Raum N2'),
    ('N3', 'Room N3', 'room_n3', 'Raum N3'),
    ('S1', 'Room S1 (seminar room)', 'room_s1', 'Raum S1 (Seminarraum)'),
    ('S4', 'Room S4 (laboratory)', 'room_s4', 'Raum S4 (Labor)');

-- Staff: `room` is a room of the table above; `whereabouts` is what the robot says when a
-- visitor asks for the person.
CREATE TABLE IF NOT EXISTS staff (
    name        TEXT PRIMARY KEY,
    label       TEXT NOT NULL,
    room        TEXT NOT NULL REFERENCES rooms (name),
    whereabouts TEXT NOT NULL,
    label_de    TEXT NOT NULL DEFAULT '',
    whereabouts_de TEXT NOT NULL DEFAULT ''
);
INSERT OR REPLACE INTO staff (name, label, room, whereabouts, label_de, whereabouts_de) VALUES
    ('weber', 'Dr. Weber', 'N1',
     'Dr. Weber works in room N1, at the west end of the hallway. In the afternoons she teaches in the seminar room S1.',
     'Dr. Weber',
     'Frau Dr. Weber arbeitet in Raum N1, am westlichen Ende des Flurs. Nachmittags unterrichtet sie im Seminarraum S1.'),
    ('gross', 'Prof. Gross', 'N2',
     'Professor Gross has his office in room N2. He is usually there in the mornings.',
     'Prof. Gross',
     'Professor Gross hat sein Büro in Raum N2. Er ist meistens vormittags da.'),
    ('klein', 'Ms. Klein', 'N3',
     'Ms. Klein is in room N3, just across the hallway. She is the secretary and knows where everyone is.',
     'Frau Klein',
     'Frau Klein ist in Raum N3, gleich gegenüber auf dem Flur. Sie ist die Sekretärin und weiß, wo alle sind.'),
    ('lang', 'Dr. Lang', 'S4',
     'Dr. Lang is mostly in the laboratory, room S4, at the east end.',
     'Dr. Lang',
     'Dr. Lang ist meistens im Labor, Raum S4, am östlichen Ende.');

-- Where each staff member's room is on the map (what the guide leads to).
CREATE VIEW IF NOT EXISTS staff_places AS
    SELECT staff.name AS name, rooms.place AS place
    FROM staff JOIN rooms ON rooms.name = staff.room;
