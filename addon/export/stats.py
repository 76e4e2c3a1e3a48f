"""Counters of what a sync sent to the native core; tests read them to check incremental updates."""
from dataclasses import dataclass, field


@dataclass
class SyncStats:
    syncs: int = 0
    meshes_exported: int = 0          # bounce_mesh_set calls
    triangles_exported: int = 0
    meshes_removed: int = 0
    instance_syncs: int = 0           # bounce_instances_set calls
    material_syncs: int = 0
    texture_uploads: int = 0
    light_syncs: int = 0
    world_syncs: int = 0
    last_sync_seconds: float = 0.0    # wall time of the last sync, everything included
    last_geometry_seconds: float = 0.0  # part of it spent reading and uploading meshes
    last_triangles_exported: int = 0
    last_instance_count: int = 0
    last_light_count: int = 0
    last_light_names: list = field(default_factory=list)  # in the order the lights were sent
    history: list = field(default_factory=list, repr=False)  # (sync seconds, triangles exported) per sync

    def record_sync(self, seconds, geometry_seconds, triangles):
        self.syncs += 1
        self.last_sync_seconds = seconds
        self.last_geometry_seconds = geometry_seconds
        self.last_triangles_exported = triangles
        self.history.append((seconds, triangles))
        del self.history[:-100]

    def seconds_per_million_triangles(self):
        """Sync time of the last sync per million exported triangles (None when it exported none)."""
        if not self.last_triangles_exported:
            return None
        return self.last_sync_seconds * 1e6 / self.last_triangles_exported

    def as_dict(self):
        return {k: v for k, v in self.__dict__.items() if k != "history"}
