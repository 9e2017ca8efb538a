-- The shopping assistant's database: the store's products and categories (edit these to your
-- store), and what the robot writes: the customers' choices, their searches, the guide runs.
-- This file runs at every start: keep it safe to run twice (IF NOT EXISTS, OR REPLACE).
CREATE TABLE IF NOT EXISTS answers (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,   -- one run of `interbot run`
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,   -- one customer within the run
    question    TEXT    NOT NULL,
    answer      TEXT    NOT NULL,
    robot_time  REAL    NOT NULL,   -- s since the run started
    wall_time   REAL    NOT NULL    -- Unix time
);

-- Every search a customer made on the screen (a category pressed or a name typed) and how it
-- came out: exact, close (the robot asked "did you mean …?") or none. For the store: what do
-- customers look for that it does not have, and which names do they misspell?
CREATE TABLE IF NOT EXISTS searches (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,
    robot       TEXT    NOT NULL,
    session     INTEGER NOT NULL,
    question    TEXT    NOT NULL,
    query       TEXT    NOT NULL,   -- what the customer typed or pressed
    outcome     TEXT    NOT NULL,   -- exact, close or none
    found       TEXT,               -- the catalogue name found, else NULL
    score       REAL    NOT NULL,   -- similarity 0..1 of the best match
    robot_time  REAL    NOT NULL,
    wall_time   REAL    NOT NULL
);

-- One row per guide run (written by the robot): where to, how it ended, why, how long.
CREATE TABLE IF NOT EXISTS guide_runs (
    id          INTEGER PRIMARY KEY AUTOINCREMENT,
    run_id      TEXT    NOT NULL,
    robot       TEXT    NOT NULL,
    place       TEXT    NOT NULL,
    outcome     TEXT    NOT NULL,
    reason      TEXT    NOT NULL,
    duration    REAL    NOT NULL,
    robot_time  REAL    NOT NULL,
    wall_time   REAL    NOT NULL
);

-- The categories on the screen's buttons: `name` is recorded, `label` is the button, `place`
-- the shelf of the robot's map (robots/floors/store.toml) the robot takes the customer to.
CREATE TABLE IF NOT EXISTS categories (
    name    TEXT PRIMARY KEY,
    label   TEXT NOT NULL,
    aisle   TEXT NOT NULL,
    place   TEXT NOT NULL,
    aliases TEXT NOT NULL DEFAULT '',  -- other words for it, comma-separated
    label_de TEXT NOT NULL DEFAULT ''  -- the button in German (dialog.xml languages="en de")
);
INSERT OR REPLACE INTO categories (name, label, aisle, place, aliases, label_de) VALUES
    ('bakery',    'Bread and bakery',  'A1', 'shelf_bakery',    'bread,cakes', 'Brot und Backwaren'),
    ('breakfast', 'Breakfast cereals', 'A1', 'shelf_cereal',    'cereal,cereals,muesli', 'Frühstücksflocken'),
    ('coffee',    'Coffee and tea',    'A2', 'shelf_coffee',    'tea', 'Kaffee und Tee'),
    ('pasta',     'Pasta and rice',    'A2', 'shelf_pasta',     'noodles,rice', 'Nudeln und Reis'),
    ('canned',    'Canned food',       'A3', 'shelf_canned',    'tins,cans', 'Konserven'),
    ('snacks',    'Snacks and sweets', 'A4', 'shelf_snacks',    'sweets,candy,chips', 'Snacks und Süßigkeiten'),
    ('drinks',    'Drinks',            'A4', 'shelf_drinks',    'beverages,water,juice', 'Getränke'),
    ('household', 'Household',         'A5', 'shelf_household', 'cleaning', 'Haushalt'),
    ('dairy',     'Dairy',             'back wall', 'shelf_dairy', 'milk products', 'Milchprodukte'),
    ('produce',   'Fruit and vegetables', 'produce', 'shelf_produce', 'fruit,vegetables', 'Obst und Gemüse');

-- The products: `name` is what the robot records and says, `label` how it is written, the
-- category, the aisle and the shelf place on the map, which shelf board, the price in euros,
-- and other names customers type for it (comma-separated).
CREATE TABLE IF NOT EXISTS products (
    name     TEXT PRIMARY KEY,
    label    TEXT NOT NULL,
    category TEXT NOT NULL REFERENCES categories (name),
    aisle    TEXT NOT NULL,
    place    TEXT NOT NULL,
    board    TEXT NOT NULL,            -- e.g. 'top shelf', 'at eye level'
    price    REAL NOT NULL,            -- euros
    aliases  TEXT NOT NULL DEFAULT ''
);
INSERT OR REPLACE INTO products (name, label, category, aisle, place, board, price, aliases) VALUES
    ('wholemeal bread', 'Wholemeal bread 500 g', 'bakery', 'A1', 'shelf_bakery', 'at eye level', 2.49, 'brown bread'),
    ('croissants',      'Croissants, 4 pieces',  'bakery', 'A1', 'shelf_bakery', 'top shelf', 1.99, 'croissant'),
    ('muesli',          'Muesli 750 g',          'breakfast', 'A1', 'shelf_cereal', 'at eye level', 3.29, 'granola'),
    ('cornflakes',      'Cornflakes 500 g',      'breakfast', 'A1', 'shelf_cereal', 'bottom shelf', 2.19, ''),
    ('espresso',        'Espresso beans 1 kg',   'coffee', 'A2', 'shelf_coffee', 'at eye level', 12.99, 'coffee beans'),
    ('ground coffee',   'Ground coffee 500 g',   'coffee', 'A2', 'shelf_coffee', 'top shelf', 5.49, 'filter coffee'),
    ('green tea',       'Green tea, 20 bags',    'coffee', 'A2', 'shelf_coffee', 'bottom shelf', 2.79, ''),
    ('spaghetti',       'Spaghetti 500 g',       'pasta', 'A2', 'shelf_pasta', 'at eye level', 1.29, ''),
    ('basmati rice',    'Basmati rice 1 kg',     'pasta', 'A2', 'shelf_pasta', 'bottom shelf', 2.99, 'rice'),
    ('tomatoes',        'Chopped tomatoes, can', 'canned', 'A3', 'shelf_canned', 'at eye level', 0.89, 'tomato'),
    ('chickpeas',       'Chickpeas, can',        'canned', 'A3', 'shelf_canned', 'bottom shelf', 0.99, ''),
    ('paprika',         'Paprika powder',        'canned', 'A3', 'shelf_spices', 'at eye level', 1.79, 'spices'),
    ('chocolate',       'Dark chocolate 100 g',  'snacks', 'A4', 'shelf_snacks', 'at eye level', 1.49, ''),
    ('crisps',          'Potato crisps 200 g',   'snacks', 'A4', 'shelf_snacks', 'top shelf', 1.99, 'chips'),
    ('orange juice',    'Orange juice 1 l',      'drinks', 'A4', 'shelf_drinks', 'at eye level', 2.29, ''),
    ('mineral water',   'Mineral water, 6 x 1.5 l', 'drinks', 'A4', 'shelf_drinks', 'bottom shelf', 3.49, 'sparkling water'),
    ('dish soap',       'Dish soap 500 ml',      'household', 'A5', 'shelf_household', 'at eye level', 1.59, 'washing-up liquid'),
    ('cat food',        'Cat food, 12 pouches',  'household', 'A5', 'shelf_petfood', 'bottom shelf', 6.99, 'pet food'),
    ('milk',            'Fresh milk 1 l',        'dairy', 'back wall', 'shelf_dairy', 'in the fridge', 1.15, ''),
    ('yoghurt',         'Natural yoghurt 500 g', 'dairy', 'back wall', 'shelf_dairy', 'in the fridge', 0.99, 'yogurt'),
    ('bananas',         'Bananas, per kg',       'produce', 'produce', 'shelf_produce', 'on the island', 1.69, 'banana');

-- German names of the categories and products (the row's name is the key): `label` is what
-- a German customer reads and hears, `aliases` what they may type. The search finds a row by
-- these too ("Milch", "Bananen"), and says and shows the German label in a German run. A row
-- without one here is known by its English names only. A table of its own, so an older
-- database file keeps working when this file runs on it again.
CREATE TABLE IF NOT EXISTS names_de (
    name    TEXT PRIMARY KEY,
    label   TEXT NOT NULL,
    aliases TEXT NOT NULL DEFAULT ''
);
INSERT OR REPLACE INTO names_de (name, label, aliases) VALUES
    ('bakery',          'Brot und Backwaren',        'Brot,Backwaren,Kuchen,Bäckerei'),
    ('breakfast',       'Frühstücksflocken',         'Frühstück,Flocken,Cerealien'),
    ('coffee',          'Kaffee und Tee',            'Kaffee,Tee'),
    ('pasta',           'Nudeln und Reis',           'Nudeln,Reis,Teigwaren'),
    ('canned',          'Konserven',                 'Dosen,Dosenessen'),
    ('snacks',          'Snacks und Süßigkeiten',    'Süßigkeiten,Knabbereien'),
    ('drinks',          'Getränke',                  'Wasser,Saft'),
    ('household',       'Haushalt',                  'Putzmittel,Reinigung'),
    ('dairy',           'Milchprodukte',             'Molkereiprodukte'),
    ('produce',         'Obst und Gemüse',           'Obst,Gemüse'),
    ('wholemeal bread', 'Vollkornbrot 500 g',        'Vollkornbrot,Schwarzbrot'),
    ('croissants',      'Croissants, 4 Stück',       'Hörnchen'),
    ('muesli',          'Müsli 750 g',               'Müsli'),
    ('cornflakes',      'Cornflakes 500 g',          ''),
    ('espresso',        'Espressobohnen 1 kg',       'Kaffeebohnen'),
    ('ground coffee',   'Gemahlener Kaffee 500 g',   'Filterkaffee,Kaffeepulver'),
    ('green tea',       'Grüner Tee, 20 Beutel',     'Grüntee'),
    ('spaghetti',       'Spaghetti 500 g',           ''),
    ('basmati rice',    'Basmatireis 1 kg',          'Basmati'),
    ('tomatoes',        'Gehackte Tomaten, Dose',    'Tomaten,Tomate'),
    ('chickpeas',       'Kichererbsen, Dose',        'Kichererbsen'),
    ('paprika',         'Paprikapulver',             'Paprika,Gewürze'),
    ('chocolate',       'Zartbitterschokolade 100 g', 'Schokolade'),
    ('crisps',          'Kartoffelchips 200 g',      'Chips'),
    ('orange juice',    'Orangensaft 1 l',           'Orangensaft,O-Saft'),
    ('mineral water',   'Mineralwasser, 6 x 1,5 l',  'Mineralwasser,Sprudel'),
    ('dish soap',       'Spülmittel 500 ml',         'Spülmittel'),
    ('cat food',        'Katzenfutter, 12 Beutel',   'Katzenfutter,Tierfutter'),
    ('milk',            'Frische Milch 1 l',         'Milch,Vollmilch'),
    ('yoghurt',         'Naturjoghurt 500 g',        'Joghurt,Jogurt'),
    ('bananas',         'Bananen, pro kg',           'Bananen,Banane');

-- What a customer can ask for, one name each: the categories, then the products, with their
-- German names. The robot searches this view (dialog.xml search="catalogue") and takes the
-- place and the words it says on arrival from it.
DROP VIEW IF EXISTS catalogue;
CREATE VIEW catalogue AS
    SELECT c.name, c.label, c.name AS category, c.aliases, c.place,
           c.label || ': here in aisle ' || c.aisle || '.' AS here,
           COALESCE(d.label, NULLIF(c.label_de, '')) AS label_de, d.aliases AS aliases_de,
           COALESCE(d.label, NULLIF(c.label_de, ''), c.label) || ': hier im Gang ' || c.aisle
               || '.' AS here_de
      FROM categories c LEFT JOIN names_de d ON d.name = c.name
    UNION ALL
    SELECT p.name, p.label, p.category, p.aliases, p.place,
           p.label || ': here in aisle ' || p.aisle || ', ' || p.board || ', for ' ||
           printf('%.2f', p.price) || ' euros.' AS here,
           d.label AS label_de, d.aliases AS aliases_de,
           COALESCE(d.label, p.label) || ': hier im Gang ' || p.aisle || ', für ' ||
           replace(printf('%.2f', p.price), '.', ',') || ' Euro.' AS here_de
      FROM products p LEFT JOIN names_de d ON d.name = p.name;
