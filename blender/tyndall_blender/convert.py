"""Blender's evaluated scene as a Tyndall scene description.

`describe(depsgraph, settings)` reads what Blender would render at the
current frame (modifiers applied, instances expanded: the evaluated
depsgraph) and returns the dict `tyndall.Scene.from_dict` takes — the
native scene format of docs/scene-format.md as nested dicts — and the
warnings for what it could not carry, one per material or object.

Units and conventions (each checked against Cycles by tests/):

* Coordinates: Blender's metres, Z up, become Tyndall's with Y up, as
  Blender's glTF exporter writes them: (x, y, z) → (x, z, −y).
* Point and spot lights of power P (W) and colour c: radiant intensity
  c·P/(4π) W/sr (Cycles' convention; the radius is not carried: Tyndall's
  lights are points). A spot's `spot_size` is the full cone angle; its
  `spot_blend` b is Cycles' smoothstep from the edge inwards, full
  intensity at cos θ = cos θc + (1 − cos θc)·b (b = 0: a hard edge).
* Suns: `energy` is the irradiance (W/m²) on a surface facing them.
* Area lights (square and rectangle): radiance c·P/(π·A) from their
  front (−Z) face, a quad light.
* Principled BSDF: glTF's metallic-roughness mix, as Blender's glTF
  exporter maps it — base colour (or an image texture on it), metallic,
  roughness, F0 = ((ior − 1)/(ior + 1))² · 2·(Specular IOR Level) ·
  Specular Tint, a clear coat of Coat Weight and Coat Roughness (its
  IOR taken as 1.5 and its tint as white, with a warning otherwise),
  emission colour × strength added over it (both faces, as Cycles' mesh
  emission); Transmission Weight ≥ ½ is a refracting
  dielectric of its IOR. Diffuse, Glossy, Emission, Transparent and
  Glass BSDFs map to Tyndall's materials of those names.
* The World: its Background colour × strength (or an equirectangular
  Environment Texture) is the environment light; its volume (Volume
  Scatter, Volume Absorption, their sum, or Principled Volume) is the
  homogeneous fog that fills all space (`[fog]`, or under volpath a
  uniform `[[media]]` volume where its extinction differs by colour).
* Volume objects (OpenVDB files, the current frame of a sequence) with a
  Principled Volume become `[[media]]` with a "vdb" density; meshes whose
  material links its Volume output are filled by a homogeneous medium of
  that shader (the mesh is its region).
* The camera: perspective, its vertical field of view from the lens,
  sensor and sensor fit; with depth of field, a thin lens of radius
  lens/(2·f-stop) focused at the focus distance (or the focus object's
  distance along the view axis), as Cycles reads it.
"""

from __future__ import annotations

import math
import os
import re
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Tuple

import numpy as np

# Blender's Z-up frame to Tyndall's Y-up one: (x, y, z) → (x, z, −y).
Z_UP_TO_Y_UP = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])

# Object types that evaluate to a mesh (curves, text, metaballs, surfaces).
MESH_LIKE = {"MESH", "CURVE", "SURFACE", "META", "FONT"}


# How far apart a medium's RGB extinctions may be (tyndall::limits::
# MAX_CHANNEL_RATIO, docs/scene-format.md "Limits").
MAX_CHANNEL_RATIO = 1000.0


def uniform_medium(sigma_s: np.ndarray, sigma_t: np.ndarray, g: float) -> Dict[str, Any]:
    """The `[[media]]` keys of a homogeneous medium of RGB scattering and
    extinction coefficients `sigma_s`, `sigma_t` (per unit length) and
    Henyey–Greenstein `g`: σt, the albedo σs/σt (0 where σt is) and g,
    clamped to what Tyndall takes."""
    albedo = np.divide(sigma_s, sigma_t, out=np.zeros(3), where=sigma_t > 0)
    return {
        "sigma_t": [float(x) for x in sigma_t],
        "albedo": [float(x) for x in np.clip(albedo, 0.0, 1.0)],
        "g": float(max(-0.999, min(0.999, g))),
    }


class ConversionError(Exception):
    """A scene Tyndall cannot render, with a message naming the object."""


@dataclass
class Settings:
    """The engine's settings for one render (properties.TyndallSettings)."""

    integrator: str = "volpath"
    spp: int = 64
    max_depth: int = 0
    seed: int = 0


@dataclass
class Description:
    """A scene dict for `tyndall.Scene.from_dict` and the warnings made."""

    scene: Dict[str, Any]
    warnings: List[str] = field(default_factory=list)


def to_y_up(v) -> List[float]:
    """A Blender position or direction in Tyndall's frame."""
    return [float(x) for x in Z_UP_TO_Y_UP @ np.asarray(v, dtype=np.float64)]


def _matrix(m) -> np.ndarray:
    return np.array([list(row) for row in m], dtype=np.float64)


class _Converter:
    def __init__(self, depsgraph, settings: Settings, blender_version: Tuple[int, int, int]):
        self.depsgraph = depsgraph
        self.blender_version = blender_version
        # The scene as evaluated at the depsgraph's frame (animated
        # cameras, lights and World values).
        self.scene = depsgraph.scene_eval
        self.settings = settings
        self.warnings: List[str] = []
        self.materials: Dict[str, Dict[str, Any]] = {}
        # Blender material name (or None) → Tyndall material key.
        self.material_keys: Dict[Optional[str], str] = {}
        self.shapes: List[Dict[str, Any]] = []
        self.lights: List[Dict[str, Any]] = []
        self.media: List[Dict[str, Any]] = []
        # The view layer's light groups: Cycles renders only these.
        view_layer = getattr(depsgraph, "view_layer", None)
        self.light_groups = {g.name for g in getattr(view_layer, "lightgroups", ())}

    def warn(self, message: str) -> None:
        if message not in self.warnings:
            self.warnings.append(message)

    def light_group(self, owner, what: str) -> Optional[str]:
        """The light group of `owner` (an object or the World) if the view
        layer renders it, as Cycles does; `what` names it in warnings."""
        name = getattr(owner, "lightgroup", "")
        if not name or name not in self.light_groups:
            return None
        if not LIGHT_GROUP_NAME.fullmatch(name):
            self.warn(f"{what}: light group '{name}' is not a Tyndall group name (letters, digits, _ and -); its light is in no group")
            return None
        return name

    # -- the whole scene ---------------------------------------------------

    def describe(self) -> Description:
        camera = self.camera()
        for instance in self.depsgraph.object_instances:
            obj = instance.object
            matrix = _matrix(instance.matrix_world)
            if obj.type in MESH_LIKE:
                self.mesh_object(obj, matrix)
            elif obj.type == "LIGHT":
                self.light_object(obj, matrix)
            elif obj.type == "VOLUME":
                self.volume_object(obj, matrix)
        environment, fog = self.world()
        if environment is not None:
            group = self.light_group(self.scene.world, f"world '{self.scene.world.name}'")
            if group is not None:
                environment["light_group"] = group
            self.lights.append(environment)
        scene: Dict[str, Any] = {"camera": camera, "render": self.render_table()}
        if fog is not None:
            scene["fog"] = fog
        if self.materials:
            scene["materials"] = self.materials
        if self.shapes:
            scene["shapes"] = self.shapes
        if self.lights:
            scene["lights"] = self.lights
        if self.media:
            scene["media"] = self.media
        return Description(scene, self.warnings)

    def resolution(self) -> Tuple[int, int]:
        r = self.scene.render
        scale = r.resolution_percentage / 100.0
        return max(1, int(r.resolution_x * scale)), max(1, int(r.resolution_y * scale))

    def render_table(self) -> Dict[str, Any]:
        width, height = self.resolution()
        table: Dict[str, Any] = {
            "width": width,
            "height": height,
            "spp": int(self.settings.spp),
            "seed": int(self.settings.seed),
            "integrator": self.settings.integrator,
        }
        if self.settings.max_depth > 0:
            table["max_depth"] = int(self.settings.max_depth)
        return table

    # -- camera ------------------------------------------------------------

    def camera(self) -> Dict[str, Any]:
        if self.scene.camera is None:
            raise ConversionError(f"scene '{self.scene.name}' has no camera: add one and make it active")
        cam = self.scene.camera.evaluated_get(self.depsgraph)
        data = cam.data
        if data.type != "PERSP":
            raise ConversionError(
                f"camera '{cam.name}': only perspective cameras are rendered (it is {data.type.lower()})"
            )
        if data.shift_x != 0.0 or data.shift_y != 0.0:
            self.warn(f"camera '{cam.name}': lens shift is ignored")
        r = self.scene.render
        if r.pixel_aspect_x != r.pixel_aspect_y:
            self.warn(f"scene '{self.scene.name}': non-square pixels are ignored")
        width, height = self.resolution()
        fov_y = vertical_fov(data.sensor_fit, data.lens, data.sensor_width, data.sensor_height, width, height)
        m = _matrix(cam.matrix_world)
        position = m[:3, 3]
        forward = -m[:3, 2]
        up = m[:3, 1]
        table = {
            "position": to_y_up(position),
            "look_at": to_y_up(position + forward),
            "up": to_y_up(up),
            "fov_y_deg": math.degrees(fov_y),
        }
        if data.dof.use_dof:
            table.update(self.thin_lens(cam, data, m))
        return table

    def thin_lens(self, cam, data, m: np.ndarray) -> Dict[str, float]:
        """The camera table's lens keys for Blender's depth of field, as
        Cycles reads it: aperture radius = lens/(2·f-stop) (lens in mm,
        so ·10⁻³ m), the focus distance that of the focus object along the
        view axis when there is one."""
        dof = data.dof
        radius = data.lens * 1e-3 / (2.0 * max(float(dof.aperture_fstop), 1e-5))
        if dof.focus_object is not None:
            target = _matrix(dof.focus_object.evaluated_get(self.depsgraph).matrix_world)[:3, 3]
            axis = m[:3, 2] / np.linalg.norm(m[:3, 2])
            focus = abs(float(np.dot(axis, m[:3, 3] - target)))
        else:
            focus = float(dof.focus_distance)
        if focus <= 0.0:
            self.warn(f"camera '{cam.name}': its focus distance is 0, so depth of field is left out")
            return {}
        if dof.aperture_blades >= 3:
            self.warn(f"camera '{cam.name}': its {dof.aperture_blades}-blade aperture is rendered round")
        if abs(float(dof.aperture_ratio) - 1.0) > 1e-6:
            self.warn(f"camera '{cam.name}': its aperture ratio is ignored (a round aperture)")
        return {"aperture_radius": radius, "focus_distance": focus}

    # -- meshes ------------------------------------------------------------

    def mesh_object(self, obj, matrix: np.ndarray) -> None:
        try:
            mesh = obj.to_mesh()
        except RuntimeError:
            mesh = None
        if mesh is None:
            return
        try:
            self.add_mesh(obj, mesh, matrix)
        finally:
            obj.to_mesh_clear()

    def add_mesh(self, obj, mesh, matrix: np.ndarray) -> None:
        mesh.calc_loop_triangles()
        n = len(mesh.loop_triangles)
        if n == 0:
            return
        loops = np.empty(3 * n, dtype=np.int64)
        mesh.loop_triangles.foreach_get("loops", loops)
        vertices = np.empty(3 * n, dtype=np.int64)
        mesh.loop_triangles.foreach_get("vertices", vertices)
        slots = np.empty(n, dtype=np.int64)
        mesh.loop_triangles.foreach_get("material_index", slots)
        co = np.empty(3 * len(mesh.vertices), dtype=np.float64)
        mesh.vertices.foreach_get("co", co)
        normals = np.empty(3 * len(mesh.loops), dtype=np.float64)
        mesh.corner_normals.foreach_get("vector", normals)
        linear = matrix[:3, :3]
        to_world = Z_UP_TO_Y_UP @ linear
        positions = co.reshape(-1, 3)[vertices] @ to_world.T + Z_UP_TO_Y_UP @ matrix[:3, 3]
        normal_matrix = Z_UP_TO_Y_UP @ np.linalg.inv(linear).T
        corner_normals = normals.reshape(-1, 3)[loops] @ normal_matrix.T
        lengths = np.linalg.norm(corner_normals, axis=1, keepdims=True)
        corner_normals = corner_normals / np.where(lengths > 0, lengths, 1.0)
        uv_layer = mesh.uv_layers.active
        uvs = None
        if uv_layer is not None:
            all_uvs = np.empty(2 * len(mesh.loops), dtype=np.float64)
            uv_layer.uv.foreach_get("vector", all_uvs)
            uvs = all_uvs.reshape(-1, 2)[loops]
            # Blender's v runs up its images, Tyndall's (glTF's) down.
            uvs[:, 1] = 1.0 - uvs[:, 1]
        corners = np.arange(3 * n).reshape(-1, 3)
        if np.linalg.det(linear) < 0:
            # A mirroring transform turns the winding: keep fronts in front.
            corners = corners[:, [0, 2, 1]]
        materials = [slot.material for slot in obj.material_slots] or [None]
        for slot in np.unique(slots):
            material = materials[min(int(slot), len(materials) - 1)]
            chosen = corners[slots == slot].reshape(-1)
            surface, volume = shader_outputs(material)
            if volume is not None:
                self.mesh_volume(obj, material, volume, positions[chosen], vertices[chosen])
            if volume is not None and not surface:
                continue
            key, textured = self.material(material, obj)
            shape: Dict[str, Any] = {
                "type": "triangles",
                "positions": positions[chosen].astype(np.float32).reshape(-1),
                "indices": np.arange(len(chosen), dtype=np.int64),
                "normals": corner_normals[chosen].astype(np.float32).reshape(-1),
                "material": key,
            }
            group = self.light_group(obj, f"object '{obj.name}'")
            if group is not None and emits(self.materials[key]):
                shape["light_group"] = group
            if uvs is not None:
                shape["uvs"] = uvs[chosen].astype(np.float32).reshape(-1)
            elif textured:
                self.warn(f"object '{obj.name}': it has no UV map, so its material's texture is left out")
                key = self.untextured(key)
                shape["material"] = key
            self.shapes.append(shape)

    def mesh_volume(self, obj, material, node, positions: np.ndarray, vertices: np.ndarray) -> None:
        """The medium a volume shader `node` of `material` fills the mesh
        of `obj` with (its triangles' world `positions`, their Blender
        vertex numbers `vertices`): homogeneous, as Cycles renders a
        mesh's volume (no attributes: density 1)."""
        where = f"object '{obj.name}'"
        emission = [0.0, 0.0, 0.0]
        coefficients = self.volume_coefficients(f"material '{material.name}'", node, emission)
        if coefficients is None:
            return
        sigma_s, sigma_a, g = coefficients
        sigma_t = sigma_s + sigma_a
        if float(sigma_t.max()) <= 0.0 and not any(emission):
            return
        # Inside is found by counting crossings: every edge must join two
        # triangles.
        edges = np.sort(vertices.reshape(-1, 3)[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
        _, counts = np.unique(edges, axis=0, return_counts=True)
        if np.any(counts != 2):
            self.warn(f"{where}: its volume needs a closed mesh (an edge has {int(counts[counts != 2][0])} faces); it is left out")
            return
        medium = uniform_medium(sigma_s, sigma_t, g)
        medium["mesh"] = {
            "positions": positions.astype(np.float32).reshape(-1),
            "indices": np.arange(len(positions), dtype=np.int64),
        }
        if any(emission):
            medium["emission"] = emission
        self.media.append(medium)

    def untextured(self, key: str) -> str:
        """The key of material `key` without its base colour texture."""
        plain = key + "-untextured"
        if plain not in self.materials:
            table = dict(self.materials[key])
            table.pop("base_color_texture", None)
            self.materials[plain] = table
        return plain

    # -- materials ---------------------------------------------------------

    def material(self, material, obj) -> Tuple[str, bool]:
        """The key of Blender `material`'s Tyndall material (made once)
        and whether it has a base colour texture."""
        name = material.name if material is not None else None
        if name not in self.material_keys:
            key = f"m{len(self.material_keys)}"
            self.material_keys[name] = key
            self.materials[key] = self.material_table(material)
        key = self.material_keys[name]
        return key, "base_color_texture" in self.materials[key]

    def material_table(self, material) -> Dict[str, Any]:
        grey = {"type": "diffuse", "reflectance": 0.8}
        if material is None:
            return default_surface(self.blender_version)
        if not material.use_nodes or material.node_tree is None:
            return {"type": "diffuse", "reflectance": [float(c) for c in material.diffuse_color[:3]]}
        output = material.node_tree.get_output_node("CYCLES") or material.node_tree.get_output_node("ALL")
        surface = output.inputs["Surface"] if output is not None else None
        if surface is None or not surface.is_linked:
            self.warn(f"material '{material.name}': it has no surface shader; rendered grey")
            return grey
        node = surface.links[0].from_node
        return self.shader(material, node) or grey

    def shader(self, material, node) -> Optional[Dict[str, Any]]:
        inputs = node.inputs
        where = f"material '{material.name}'"
        if node.bl_idname == "ShaderNodeBsdfPrincipled":
            return self.principled(material, node)
        if node.bl_idname == "ShaderNodeBsdfDiffuse":
            return {"type": "diffuse", "reflectance": self.colour(material, inputs["Color"])}
        if node.bl_idname == "ShaderNodeEmission":
            strength = self.value(material, inputs["Strength"])
            radiance = [c * strength for c in self.colour(material, inputs["Color"])]
            return {"type": "emissive", "radiance": radiance, "two_sided": True}
        if node.bl_idname == "ShaderNodeBsdfTransparent":
            return {"type": "glass", "color": self.colour(material, inputs["Color"]), "alpha": 1.0}
        if node.bl_idname == "ShaderNodeBsdfGlass":
            return {"type": "dielectric", "ior": self.value(material, inputs["IOR"])}
        if node.bl_idname in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"):
            roughness = self.value(material, inputs["Roughness"])
            colour = self.colour(material, inputs["Color"])
            if roughness == 0.0:
                return {"type": "mirror", "reflectance": colour}
            return {"type": "glossy", "reflectance": colour, "roughness": roughness * roughness}
        self.warn(f"{where}: the {node.bl_label} node is not supported; rendered grey")
        return None

    def principled(self, material, node) -> Dict[str, Any]:
        inputs = node.inputs
        where = f"material '{material.name}'"
        ignored = [
            name
            for name, key in (
                ("sheen", "Sheen Weight"),
                ("subsurface", "Subsurface Weight"),
            )
            if key in inputs and (inputs[key].is_linked or inputs[key].default_value > 0.0)
        ]
        if inputs["Alpha"].is_linked or inputs["Alpha"].default_value < 1.0:
            ignored.append("alpha")
        if inputs["Normal"].is_linked:
            ignored.append("normal map")
        if ignored:
            self.warn(f"{where}: {', '.join(ignored)} not rendered")
        ior = self.value(material, inputs["IOR"])
        transmission = self.value(material, inputs["Transmission Weight"])
        if transmission >= 0.5:
            if transmission < 1.0:
                self.warn(f"{where}: transmission {transmission:g} is rendered as 1 (clear glass)")
            return {"type": "dielectric", "ior": ior}
        if transmission > 0.0:
            self.warn(f"{where}: transmission {transmission:g} is rendered as 0 (opaque)")
        table: Dict[str, Any] = {"type": "principled"}
        base = inputs["Base Color"]
        texture = self.image_texture(material, base)
        if texture is not None:
            table["base_color"] = 1.0
            table["base_color_texture"] = texture
        else:
            table["base_color"] = self.colour(material, base)
        table["metallic"] = self.value(material, inputs["Metallic"])
        table["roughness"] = self.value(material, inputs["Roughness"])
        level = self.value(material, inputs["Specular IOR Level"])
        tint = self.colour(material, inputs["Specular Tint"])
        r0 = ((ior - 1.0) / (ior + 1.0)) ** 2 if ior > 0 else 0.0
        table["f0"] = [min(1.0, max(0.0, r0 * 2.0 * level * t)) for t in tint]
        coat = self.value(material, inputs["Coat Weight"])
        if coat > 0.0:
            table["coat"] = min(1.0, coat)
            table["coat_roughness"] = self.value(material, inputs["Coat Roughness"])
            if abs(self.value(material, inputs["Coat IOR"]) - 1.5) > 1e-6:
                self.warn(f"{where}: the coat's IOR is rendered as 1.5 (F0 0.04)")
            if any(abs(t - 1.0) > 1e-6 for t in self.colour(material, inputs["Coat Tint"])):
                self.warn(f"{where}: the coat's tint is not rendered (a clear coat)")
        strength = self.value(material, inputs["Emission Strength"])
        emission = [c * strength for c in self.colour(material, inputs["Emission Color"])]
        if any(e > 0.0 for e in emission):
            table["emission"] = emission
            table["two_sided"] = True
        return table

    def image_texture(self, material, socket) -> Optional[str]:
        """The image file of an Image Texture node linked straight into
        `socket`, if there is one Tyndall can read."""
        if not socket.is_linked:
            return None
        node = socket.links[0].from_node
        where = f"material '{material.name}'"
        if node.bl_idname != "ShaderNodeTexImage" or node.image is None:
            self.warn(f"{where}: the {node.bl_label} node into {socket.name} is not supported; its default is used")
            return None
        image = node.image
        if image.packed_file is not None or image.source != "FILE":
            self.warn(f"{where}: image '{image.name}' is not a file on disk (unpack it); its texture is left out")
            return None
        path = os.path.abspath(image.filepath_from_user())
        if os.path.splitext(path)[1].lower() not in (".png", ".jpg", ".jpeg"):
            self.warn(f"{where}: image '{image.name}' is not a PNG or JPEG; its texture is left out")
            return None
        if node.inputs["Vector"].is_linked:
            self.warn(f"{where}: the texture coordinates into '{node.name}' are ignored (the UV map is used)")
        return path

    def colour(self, material, socket) -> List[float]:
        if socket.is_linked:
            self.warn(
                f"material '{material.name}': the node into {socket.name} is not supported; its default is used"
            )
        return [float(c) for c in socket.default_value[:3]]

    def value(self, material, socket) -> float:
        if socket.is_linked:
            self.warn(
                f"material '{material.name}': the node into {socket.name} is not supported; its default is used"
            )
        return float(socket.default_value)

    # -- volume objects ----------------------------------------------------

    def volume_object(self, obj, matrix: np.ndarray) -> None:
        """A Volume object (an OpenVDB file, or a frame of a sequence as a
        simulation cache writes them) shaded by a Principled Volume, as a
        `[[media]]` volume with a "vdb" density (volpath renders it)."""
        where = f"object '{obj.name}'"
        grids = obj.data.grids
        if not grids.load():
            self.warn(f"{where}: its OpenVDB file could not be read ({grids.error_message}); it is left out")
            return
        import bpy

        # The frame's file, a blend-relative path ("//…") made absolute.
        path = os.path.abspath(bpy.path.abspath(grids.frame_filepath))
        names = {grid.name for grid in grids}
        material = obj.active_material
        shading = self.volume_shading(material, where)
        if shading is None:
            return
        grid = shading.pop("grid")
        if grid not in names:
            self.warn(f"{where}: its density attribute '{grid}' is not a grid of {path}; it is left out")
            return
        medium: Dict[str, Any] = {"density": "vdb", "file": path, "grid": grid}
        medium.update(shading)
        temperature = medium.get("temperature_grid")
        if temperature is not None and temperature not in names:
            self.warn(f"{where}: its temperature attribute '{temperature}' is not a grid of {path}; no blackbody emission")
            for key in ("temperature_grid", "temperature_scale", "blackbody_law", "blackbody_intensity", "blackbody_tint"):
                medium.pop(key, None)
        emission = medium.get("emission_grid")
        if emission is not None and emission not in names:
            self.warn(f"{where}: its emission attribute '{emission}' is not a grid of {path}; no emission")
            medium.pop("emission_grid")
            medium.pop("emission")
        medium.update(self.placement(where, matrix))
        self.media.append(medium)

    def volume_shading(self, material, where: str) -> Optional[Dict[str, Any]]:
        """The medium keys of a volume material's Principled Volume (no
        material: Cycles' default volume, a Principled Volume with its
        defaults), with "grid" the density attribute; None if it cannot
        be rendered (warned)."""
        if material is None:
            return {"grid": "density", "sigma_t": 1.0, "albedo": 0.5, "g": 0.0}
        where = f"material '{material.name}'"
        output = material.node_tree.get_output_node("CYCLES") if material.node_tree is not None else None
        volume = output.inputs["Volume"] if output is not None else None
        if volume is None or not volume.is_linked:
            self.warn(f"{where}: it has no volume shader; the volume is left out")
            return None
        node = volume.links[0].from_node
        if node.bl_idname != "ShaderNodeVolumePrincipled":
            self.warn(f"{where}: the {node.bl_label} volume node is not supported (use Principled Volume); the volume is left out")
            return None
        inputs = node.inputs
        density = self.value(material, inputs["Density"])
        c = np.array(self.colour(material, inputs["Color"]))
        a = np.array(self.colour(material, inputs["Absorption Color"]))
        sigma_t = density * (c + principled_absorption(c, a))
        albedo = np.divide(c * density, sigma_t, out=np.zeros(3), where=sigma_t > 0)
        grid = inputs["Density Attribute"].default_value
        if not grid:
            # Cycles then fills the grids' bounds with the constant Density.
            self.warn(f"{where}: a Principled Volume without a Density Attribute is not rendered on a Volume object")
            return None
        table: Dict[str, Any] = {
            "grid": grid,
            "sigma_t": [float(x) for x in sigma_t],
            "albedo": [float(x) for x in np.clip(albedo, 0.0, 1.0)],
            "g": self.value(material, inputs["Anisotropy"]),
        }
        if inputs["Color Attribute"].default_value:
            self.warn(f"{where}: its colour attribute '{inputs['Color Attribute'].default_value}' is ignored")
        strength = inputs["Emission Strength"]
        emission_colour = self.colour(material, inputs["Emission Color"])
        if strength.is_linked:
            source = strength.links[0].from_node
            if source.bl_idname == "ShaderNodeAttribute" and source.attribute_name:
                # Cycles: j = attribute × Emission Color per unit length.
                table["emission"] = emission_colour
                table["emission_grid"] = source.attribute_name
            else:
                self.warn(f"{where}: the {source.bl_label} node into Emission Strength is not supported; no emission")
        elif strength.default_value > 0.0:
            self.warn(
                f"{where}: a constant Emission Strength is not rendered (drive it by a grid's Attribute node)"
            )
        intensity = self.value(material, inputs["Blackbody Intensity"])
        if intensity > 0.0:
            table["temperature_grid"] = inputs["Temperature Attribute"].default_value or "temperature"
            table["temperature_scale"] = self.value(material, inputs["Temperature"])
            table["blackbody_law"] = "cycles"
            table["blackbody_intensity"] = min(1.0, intensity)
            table["blackbody_tint"] = self.colour(material, inputs["Blackbody Tint"])
        return table

    def placement(self, where: str, matrix: np.ndarray) -> Dict[str, Any]:
        """A medium's `translate`, `scale` and `rotate_deg` for the object
        transform `matrix` after Blender's Z-up to Tyndall's Y-up."""
        linear = Z_UP_TO_Y_UP @ matrix[:3, :3]
        scale = np.linalg.norm(linear, axis=0)
        rotation = linear / scale
        if np.linalg.det(rotation) < 0:
            scale[0] = -scale[0]
            rotation[:, 0] = -rotation[:, 0]
        if np.abs(rotation.T @ rotation - np.eye(3)).max() > 1e-4:
            self.warn(f"{where}: its transform shears; it is placed by the nearest scale and rotation")
        return {
            "translate": to_y_up(matrix[:3, 3]),
            "scale": [float(x) for x in scale],
            "rotate_deg": [math.degrees(a) for a in euler_xyz(rotation)],
        }

    # -- lights ------------------------------------------------------------

    def light_object(self, obj, matrix: np.ndarray) -> None:
        data = obj.data
        # Blender's light exposure (stops) scales its power, as in Cycles.
        colour = np.array(data.color[:3], dtype=np.float64) * 2.0 ** float(getattr(data, "exposure", 0.0))
        position = to_y_up(matrix[:3, 3])
        axis = matrix[:3, :3] @ np.array([0.0, 0.0, -1.0])
        direction = to_y_up(axis / np.linalg.norm(axis))
        count = len(self.lights)
        if data.type == "POINT":
            self.lights.append(
                {"type": "point", "position": position, "intensity": list(colour * data.energy / (4 * math.pi))}
            )
        elif data.type == "SPOT":
            # Blender's spot_size is at most 180°: a half-angle ≤ 90°.
            light = {
                "type": "spot",
                "position": position,
                "direction": direction,
                "cutoff_deg": math.degrees(data.spot_size) / 2.0,
                "intensity": list(colour * data.energy / (4 * math.pi)),
            }
            blend = float(data.spot_blend)
            if blend > 0.0:
                cos_outer = math.cos(data.spot_size / 2.0)
                cos_inner = cos_outer + (1.0 - cos_outer) * blend
                light["profile"] = "smooth"
                light["inner_deg"] = math.degrees(math.acos(min(1.0, cos_inner)))
            else:
                light["profile"] = "hard"
            self.lights.append(light)
        elif data.type == "SUN":
            self.lights.append({"type": "directional", "direction": direction, "irradiance": list(colour * data.energy)})
        elif data.type == "AREA":
            self.area_light(obj, data, matrix, colour)
        group = self.light_group(obj, f"light '{obj.name}'")
        if group is not None:
            for light in self.lights[count:]:
                light["light_group"] = group

    def area_light(self, obj, data, matrix: np.ndarray, colour: np.ndarray) -> None:
        if getattr(data, "spread", math.pi) < math.pi:
            self.warn(f"light '{obj.name}': its spread is ignored (Tyndall's area lights emit over 180°)")
        if data.shape not in ("SQUARE", "RECTANGLE"):
            self.warn(f"light '{obj.name}': {data.shape.lower()} area lights are not supported; it is left out")
            return
        sx = data.size
        sy = data.size if data.shape == "SQUARE" else data.size_y
        # Corners counter-clockwise seen from below (−Z, the lit side):
        # the quad's normal (c1 − c0) × (c3 − c0) is then −Z.
        local = [(-sx / 2, -sy / 2), (-sx / 2, sy / 2), (sx / 2, sy / 2), (sx / 2, -sy / 2)]
        corners = [matrix @ np.array([x, y, 0.0, 1.0]) for x, y in local]
        corners = [c[:3] for c in corners]
        area = float(np.linalg.norm(np.cross(corners[1] - corners[0], corners[3] - corners[0])))
        if area <= 0.0:
            self.warn(f"light '{obj.name}': it has no area; it is left out")
            return
        self.lights.append(
            {
                "type": "quad",
                "corners": [to_y_up(c) for c in corners],
                "radiance": list(colour * data.energy / (math.pi * area)),
            }
        )

    # -- the World ---------------------------------------------------------

    def world(self) -> Tuple[Optional[Dict[str, Any]], Optional[Dict[str, Any]]]:
        world = self.scene.world
        if world is None:
            return None, None
        if not world.use_nodes or world.node_tree is None:
            radiance = [float(c) for c in world.color[:3]]
            return (self.environment(radiance, None) if any(radiance) else None), None
        output = world.node_tree.get_output_node("CYCLES") or world.node_tree.get_output_node("ALL")
        if output is None:
            return None, None
        environment = None
        surface = output.inputs["Surface"]
        if surface.is_linked:
            node = surface.links[0].from_node
            if node.bl_idname == "ShaderNodeBackground":
                strength = float(node.inputs["Strength"].default_value)
                colour_socket = node.inputs["Color"]
                map_file = None
                if colour_socket.is_linked:
                    source = colour_socket.links[0].from_node
                    map_file = self.environment_map(world, source)
                    radiance = [strength] * 3
                else:
                    radiance = [float(c) * strength for c in colour_socket.default_value[:3]]
                if map_file is not None or any(radiance):
                    environment = self.environment(radiance, map_file)
            else:
                self.warn(f"world '{world.name}': the {node.bl_label} node is not supported; the sky is black")
        fog = None
        volume = output.inputs["Volume"]
        if volume.is_linked:
            fog = self.world_fog(world, volume.links[0].from_node)
        return environment, fog

    def world_fog(self, world, node) -> Optional[Dict[str, Any]]:
        """The homogeneous medium of the World's volume shader, filling all
        space: the grey `[fog]` table when its extinction is the same in
        every channel; else, under volpath, a uniform `[[media]]` volume
        with no region (appended to the media; None is returned), and
        under the other integrators, which render no volumes, the grey
        fog of its largest channel (warned)."""
        coefficients = self.volume_coefficients(f"world '{world.name}'", node)
        if coefficients is None:
            return None
        sigma_s, sigma_a, g = coefficients
        sigma_t = sigma_s + sigma_a
        if float(sigma_t.max()) <= 0.0:
            return None
        grey = float(sigma_t.max())
        grey_fog = {"sigma_t": grey, "albedo": [float(x) for x in np.clip(sigma_s / grey, 0.0, 1.0)], "g": g}
        if float(sigma_t.max() - sigma_t.min()) <= 1e-6 * grey:
            return grey_fog
        if self.settings.integrator != "volpath":
            self.warn(
                f"world '{world.name}': its volume's extinction differs by colour, which only volpath renders; "
                f"under {self.settings.integrator} the fog is grey, its largest channel ({grey:g})"
            )
            return grey_fog
        floor = grey / MAX_CHANNEL_RATIO
        if float(sigma_t.min()) < floor:
            self.warn(
                f"world '{world.name}': its volume's extinction {[round(float(x), 6) for x in sigma_t]} has "
                f"channels more than {MAX_CHANNEL_RATIO:g} times apart, which Tyndall's media do not take; "
                f"the weakest are raised to {floor:g}"
            )
            sigma_t = np.maximum(sigma_t, floor)
        self.media.append(uniform_medium(sigma_s, sigma_t, g))
        return None

    def environment(self, radiance: List[float], map_file: Optional[str]) -> Dict[str, Any]:
        light: Dict[str, Any] = {"type": "environment", "radiance": radiance}
        if map_file is not None:
            light["map"] = map_file
            # Blender's equirectangular map, read in the Y-up frame, is
            # Tyndall's (Mitsuba's orientation) turned a quarter turn
            # about +y; tests/test_addon.py checks it against Cycles.
            light["map_rotate_deg"] = 90.0
        return light

    def environment_map(self, world, node) -> Optional[str]:
        where = f"world '{world.name}'"
        if node.bl_idname != "ShaderNodeTexEnvironment" or node.image is None:
            self.warn(f"{where}: the {node.bl_label} node into the Background is not supported; the sky is white")
            return None
        image = node.image
        path = os.path.abspath(image.filepath_from_user())
        if image.packed_file is not None or os.path.splitext(path)[1].lower() not in (".exr", ".hdr"):
            self.warn(f"{where}: image '{image.name}' is not an OpenEXR or HDR file on disk; the sky is white")
            return None
        if node.projection != "EQUIRECTANGULAR":
            self.warn(f"{where}: only equirectangular environment maps are supported")
        if node.inputs["Vector"].is_linked:
            self.warn(f"{where}: the mapping into '{node.name}' is ignored")
        return path

    def volume_coefficients(self, where: str, node, emission: Optional[List[float]] = None):
        """(σs, σa, g) of a volume shader node tree, per unit length; `where`
        names its owner in warnings. Principled Volumes' emission (Emission
        Strength × Color, constant: a mesh's volume has no attributes) is
        added to `emission` when given, else warned about."""
        inputs = node.inputs
        zero = np.zeros(3)

        def colour(name):
            return np.array(inputs[name].default_value[:3], dtype=np.float64)

        if node.bl_idname == "ShaderNodeVolumeScatter":
            density = float(inputs["Density"].default_value)
            return colour("Color") * density, zero, float(inputs["Anisotropy"].default_value)
        if node.bl_idname == "ShaderNodeVolumeAbsorption":
            density = float(inputs["Density"].default_value)
            return zero, (1.0 - colour("Color")) * density, 0.0
        if node.bl_idname == "ShaderNodeVolumePrincipled":
            density = float(inputs["Density"].default_value)
            c = colour("Color")
            a = colour("Absorption Color")
            strength = float(inputs["Emission Strength"].default_value)
            if emission is not None and strength > 0:
                glow = colour("Emission Color") * strength
                for k in range(3):
                    emission[k] += float(glow[k])
            elif strength > 0:
                self.warn(f"{where}: the volume's emission is not rendered")
            if float(inputs["Blackbody Intensity"].default_value) > 0:
                self.warn(f"{where}: the volume's blackbody emission is not rendered (it has no temperature grid)")
            return c * density, principled_absorption(c, a) * density, float(inputs["Anisotropy"].default_value)
        if node.bl_idname == "ShaderNodeEmission" and emission is not None:
            glow = colour("Color") * float(inputs["Strength"].default_value)
            for k in range(3):
                emission[k] += float(glow[k])
            return zero, zero, 0.0
        if node.bl_idname == "ShaderNodeAddShader":
            parts = [s.links[0].from_node for s in inputs if s.is_linked]
            total_s, total_a, weighted_g = zero.copy(), zero.copy(), 0.0
            for part in parts:
                c = self.volume_coefficients(where, part, emission)
                if c is None:
                    return None
                total_s = total_s + c[0]
                total_a = total_a + c[1]
                weighted_g += c[2] * float(c[0].mean())
            g = weighted_g / float(total_s.mean()) if total_s.mean() > 0 else 0.0
            return total_s, total_a, g
        self.warn(f"{where}: the {node.bl_label} volume node is not supported; no fog")
        return None


def shader_outputs(material) -> Tuple[bool, Any]:
    """Whether `material` has a surface (no material, or one without
    nodes, has Cycles' default surface) and the shader node linked to its
    Volume output (None if unlinked)."""
    if material is None or not material.use_nodes or material.node_tree is None:
        return True, None
    output = material.node_tree.get_output_node("CYCLES") or material.node_tree.get_output_node("ALL")
    if output is None:
        return True, None
    volume = output.inputs["Volume"]
    return output.inputs["Surface"].is_linked, volume.links[0].from_node if volume.is_linked else None


def default_surface(blender_version: Tuple[int, int, int]) -> Dict[str, Any]:
    """The material Cycles gives an object without one: a Diffuse BSDF of
    0.8 up to Blender 4.5, a default Principled BSDF from Blender 5.0
    (base colour 0.8, roughness 0.5, IOR 1.5, Specular IOR Level 0.5:
    F0 = 0.04·2·0.5); tests/test_addon.py checks it against Cycles."""
    if blender_version < (5, 0, 0):
        return {"type": "diffuse", "reflectance": 0.8}
    r0 = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2
    return {"type": "principled", "base_color": 0.8, "metallic": 0.0, "roughness": 0.5, "f0": r0 * 2.0 * 0.5}


def principled_absorption(colour: np.ndarray, absorption_colour: np.ndarray) -> np.ndarray:
    """Principled Volume's absorption per unit density, as Cycles' kernel
    computes it (svm_node_principled_volume): max(1 − c, 0)·max(1 − √a, 0)
    for Color c and Absorption Color a."""
    root = np.sqrt(np.maximum(absorption_colour, 0.0))
    return np.maximum(1.0 - colour, 0.0) * np.maximum(1.0 - root, 0.0)


def euler_xyz(rotation: np.ndarray) -> Tuple[float, float, float]:
    """Angles (α, β, γ) in radians with rotation = Rz(γ)·Ry(β)·Rx(α): X
    first, as Tyndall's `rotate_deg` applies them."""
    beta = math.asin(max(-1.0, min(1.0, -float(rotation[2, 0]))))
    if abs(float(rotation[2, 0])) < 1.0 - 1e-9:
        alpha = math.atan2(float(rotation[2, 1]), float(rotation[2, 2]))
        gamma = math.atan2(float(rotation[1, 0]), float(rotation[0, 0]))
    else:
        # Gimbal lock: only α ∓ γ is defined; take γ = 0.
        alpha = math.atan2(-float(rotation[1, 2]), float(rotation[1, 1]))
        gamma = 0.0
    return alpha, beta, gamma


# The names a Tyndall light group may take (docs/scene-format.md).
LIGHT_GROUP_NAME = re.compile(r"[A-Za-z0-9_-]{1,64}")


def emits(material: Dict[str, Any]) -> bool:
    """Whether a Tyndall material table emits light."""
    return material.get("type") == "emissive" or (material.get("type") == "principled" and "emission" in material)


def vertical_fov(sensor_fit: str, lens: float, sensor_width: float, sensor_height: float, width: int, height: int) -> float:
    """The full vertical field of view (radians) of a Blender camera with
    focal length `lens` (mm) on a sensor `sensor_width` × `sensor_height`
    (mm) fitted as `sensor_fit` to an image `width` × `height` pixels:
    with "AUTO" the sensor's width spans the image's larger side."""
    aspect = height / width
    if sensor_fit == "VERTICAL":
        return 2.0 * math.atan(sensor_height / (2.0 * lens))
    half_width = sensor_width / (2.0 * lens)
    if sensor_fit == "HORIZONTAL" or width >= height:
        return 2.0 * math.atan(half_width * aspect)
    return 2.0 * math.atan(half_width)


def describe(depsgraph, settings: Settings) -> Description:
    """The Tyndall scene of Blender's evaluated `depsgraph` at its frame.

    Raises ConversionError for a scene that cannot be rendered (no
    camera, a camera that is not perspective)."""
    import bpy

    return _Converter(depsgraph, settings, tuple(bpy.app.version)).describe()
