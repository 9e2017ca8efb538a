"""Pictures the tests draw themselves (robots.camera.render: a person, a face, a person placed
at a distance and bearing), named for the tests."""
from robots.camera.render import blank, draw_face, draw_person, person_at, smooth

__all__ = ["blank", "draw_face", "draw_person", "person_at", "smooth"]
