"""Navigation (L1): the grid map and its places, Monte-Carlo localization, global planning and
the local controller. Maps are environment data; the simulator's floors stay in L0."""
