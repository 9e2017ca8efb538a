-- The receptionist's database: the visitors' choices, and the rooms the robot knows.
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

-- One row per office: `name` is what the robot records, `label` what the screen shows,
-- `place` the place on the map, `directions` what the robot says; label_de and directions_de
-- are the same in German (the application's second language, dialog.xml).
CREATE TABLE IF NOT EXISTS rooms (
    name        TEXT PRIMARY KEY,
    label       TEXT NOT NULL,
    place       TEXT NOT NULL,
    directions  TEXT NOT NULL,
    label_de    TEXT NOT NULL DEFAULT '',
    directions_de TEXT NOT NULL DEFAULT ''
);
INSERT OR REPLACE INTO rooms (name, label, place, directions, label_de, directions_de) VALUES
    ('N1', 'Dr. Weber (N1)', 'room_n1',
     'Dr. Weber is in room N1: go west down the hallway, it is the last door on the right.',
     'Dr. Weber (N1)',
     'Frau Dr. Weber ist in Raum N1: gehen Sie den Flur nach Westen, es ist die letzte Tür rechts.'),
    ('N2', 'Prof. Gross (N2)', 'room_n2',
     'Professor Gross is in room N2: the second door on your right, towards the west.',
     'Prof. Gross (N2)',
     'Professor Gross ist in Raum N2: die zweite Tür rechts, Richtung Westen.'),
    ('N3', 'Ms. Klein (N3)', 'room_n3',
     'Ms. Klein is in room N3: the first door on your left, towards the east.',
     'Frau Klein (N3)',
     'Frau Klein ist in Raum N3: die erste Tür links, Richtung Osten.'),
    ('S4', 'The laboratory (S4)', 'room_s4',
     'The laboratory is room S4: go east, it is the last door on the right.',
     'Das Labor (S4)',
     'Das Labor ist Raum S4: gehen Sie nach Osten, es ist die letzte Tür rechts.');
