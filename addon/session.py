"""Native state of each RenderEngine instance.

It lives in a module dict keyed by id(render_engine), not on the Python object: when Blender frees an engine
it calls __del__ with the engine's Blender data already gone (DESIGN.md, pitfalls), and all __del__ may do is
release(id(self)).
"""

from . import native
from .export import SceneSync

FINAL, PREVIEW, VIEWPORT = "final", "preview", "viewport"

_sessions = {}   # id(render engine) -> Session, or the error message when the native engine failed to start

# The stats of the most recent session of each kind, for tests and benchmarks:
#   `latest_stats["viewport"].meshes_exported` counts mesh uploads of the newest viewport engine.
latest_stats = {}


class Session:
    def __init__(self, kind):
        self.kind = kind
        self.engine = native.Engine()  # the core reads BOUNCE_DEBUG_GL itself
        self.scene = SceneSync(self.engine)
        self.shown_reports = set()    # messages already shown (the viewport reports each once)
        self.scene_serial = 0         # bumped by the viewport whenever a sync sent something
        # Viewport drawing state
        self.render_signature = None  # (camera, settings, scene_serial) of the render started last
        self.pixels = None            # numpy buffer the latest frame is read into
        self.texture = None           # gpu.types.GPUTexture of that frame
        self.texture_serial = None    # frame serial the texture holds
        self.redraw_serial = None     # frame serial a redraw was last requested for
        latest_stats[kind] = self.scene.stats

    def close(self):
        self.texture = None
        self.engine.close()


def get(render_engine, kind):
    """The session of `render_engine`, created on first use; raises native.BounceError once if the native engine
    cannot start, and returns None after that (the error was reported already)."""
    key = id(render_engine)
    session = _sessions.get(key)
    if isinstance(session, str):
        return None
    if session is None:
        try:
            session = Session(kind)
        except native.BounceError as error:
            _sessions[key] = str(error)
            raise
        _sessions[key] = session
    return session


def find(render_engine):
    """The running session of `render_engine`, or None."""
    found = _sessions.get(id(render_engine))
    return found if isinstance(found, Session) else None


def release(render_engine_id):
    session = _sessions.pop(render_engine_id, None)
    if isinstance(session, Session):
        session.close()


def viewport_sessions():
    # list() copies in one step: a final render's thread may add or remove sessions meanwhile
    return [s for s in list(_sessions.values()) if isinstance(s, Session) and s.kind == VIEWPORT]


def release_all():
    for key in list(_sessions):
        release(key)
