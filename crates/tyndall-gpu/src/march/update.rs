//! Updating a [`GpuMarch`] in place for a changed scene or view (the live
//! viewer's sliders and keys): only what changed is written — the
//! uniforms (camera, fog, step, glass model), the light (with emissive
//! meshes' triangles), material and primitive arrays — the accumulated sum is cleared, and shadow maps are
//! rendered again only where they depend on the change. Pipelines and
//! the bind group layout are kept; a buffer whose size changes is
//! allocated anew (and the bind group with it).
//!
//! What a light's map depends on (`shaders/maps.wgsl`): its faces (the
//! light's position, direction and cutoff; a sun's also the scene's
//! bounds), the geometry, the glass materials and the glass model (the
//! tint stored per layer). Fog, intensities, the camera and the step do
//! not enter it. So a light that turns gets its own faces traced again,
//! their glass layers taking new spans after the layers handed out so
//! far (the old ones left unused, until unused layers outnumber used ones
//! and every map is rendered again, which packs the array); a change of
//! geometry, materials, glass model, map resolution or face layout (a
//! spot crossing 60° goes from one face to a cube) renders every map
//! again. Either way every texel ends up with the depth and layers a
//! fresh [`GpuMarch::new`] of the new scene would give it — only where
//! in the layer array its span lies may differ, which no lookup sees —
//! so the frames that follow are the same.

use super::{
    ACCUMULATION, BVH_NODES, FOG_ACCUMULATION, GpuMarch, LIGHT_TRIANGLES, MarchSettings, Prepared,
    SPAN_BYTES, Uploaded, make_bind_group, pixel_buffers, scratch,
};
use super::{GpuError, storage};
use crate::device::Gpu;
use crate::maps::GpuFace;
use bytemuck::Pod;
use tyndall::Scene;

/// Which shadow maps an update rendered again.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MapsRebuilt {
    /// None (no maps, or nothing they depend on changed).
    None,
    /// These lights' maps (indices in the scene's light order).
    Lights(Vec<usize>),
    /// Every light's.
    All,
}

/// What [`GpuMarch::update`] wrote to the GPU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Update {
    /// The uniforms changed (camera, fog, step, glass model, size, …).
    pub params: bool,
    pub primitives: bool,
    pub materials: bool,
    /// The lights, or an emissive mesh's triangles.
    pub lights: bool,
    /// The image size changed: the accumulation buffer was allocated anew.
    pub resized: bool,
    pub maps: MapsRebuilt,
}

/// Whether two arrays differ in any byte.
fn differ<T: Pod>(old: &[T], new: &[T]) -> bool {
    bytemuck::cast_slice::<T, u8>(old) != bytemuck::cast_slice::<T, u8>(new)
}

impl GpuMarch {
    /// Makes this march render `scene` under `settings`, writing only
    /// what differs from what it holds, and restarts the accumulation
    /// (frame 0, sums cleared). The frames that follow equal those of
    /// `GpuMarch::new(gpu, scene, settings)` with the same seed.
    ///
    /// Everything that can refuse the scene (what the GPU does not
    /// implement, a bad step, maps too large) is checked before anything
    /// is written: on such an error the march still renders the previous
    /// scene. An error after that (reading back the map counts) leaves it
    /// unusable; make a new one.
    pub fn update(
        &mut self,
        gpu: &Gpu,
        scene: &Scene,
        settings: &MarchSettings,
    ) -> Result<Update, GpuError> {
        let Prepared {
            scene: scene_buffers,
            mut params,
            light_maps,
            faces,
            texels,
        } = Prepared::new(gpu, scene, settings, Some(&self.uploaded.scene))?;
        let resolution = params.map_resolution;

        let old = &self.uploaded;
        params.frame = 0;
        let mut old_params = self.params;
        old_params.frame = 0;
        let mut update = Update {
            params: bytemuck::bytes_of(&params) != bytemuck::bytes_of(&old_params),
            primitives: differ(&old.scene.primitives, &scene_buffers.primitives),
            materials: differ(&old.scene.materials, &scene_buffers.materials),
            lights: differ(&old.scene.lights, &scene_buffers.lights)
                || differ(&old.scene.light_triangles, &scene_buffers.light_triangles),
            resized: params.half_extent_resolution[2..] != self.params.half_extent_resolution[2..],
            maps: MapsRebuilt::None,
        };
        let map_layout_changed = resolution != self.params.map_resolution
            || differ(&old.light_maps, &light_maps)
            || faces.len() != old.faces.len();
        let faces_changed = differ(&old.faces, &faces);
        let light_maps_changed = differ(&old.light_maps, &light_maps);
        let all_maps = resolution > 0
            && (map_layout_changed
                || update.primitives
                || update.materials
                || params.glass_model != self.params.glass_model);
        let moved_lights: Vec<usize> = if resolution > 0 && !all_maps {
            light_maps
                .iter()
                .enumerate()
                .filter(|(_, map)| {
                    let range = map.face_range();
                    differ(&old.faces[range.clone()], &faces[range])
                })
                .map(|(i, _)| i)
                .collect()
        } else {
            Vec::new()
        };

        // Nothing is refused from here on.
        let mut rebind = false;
        if update.primitives {
            rebind |= self.rewrite(gpu, 0, "primitives", &scene_buffers.primitives);
            rebind |= self.rewrite(gpu, BVH_NODES, "BVH nodes", &scene_buffers.bvh_nodes);
        }
        if update.materials {
            rebind |= self.rewrite(gpu, 1, "materials", &scene_buffers.materials);
        }
        if update.lights {
            rebind |= self.rewrite(gpu, 2, "lights", &scene_buffers.lights);
            rebind |= self.rewrite(
                gpu,
                LIGHT_TRIANGLES,
                "light triangles",
                &scene_buffers.light_triangles,
            );
        }
        if update.resized {
            for (index, buffer) in pixel_buffers(gpu, settings.width, settings.height) {
                self.buffers[index] = buffer;
            }
            rebind = true;
        }
        if faces_changed {
            rebind |= self.rewrite(gpu, 4, "faces", &faces);
        }
        if light_maps_changed {
            rebind |= self.rewrite(gpu, 5, "light maps", &light_maps);
        }
        if map_layout_changed {
            self.buffers[6] = scratch(gpu, "map depths", texels * 4);
            self.buffers[7] = scratch(gpu, "layer spans", texels * SPAN_BYTES);
            rebind = true;
        }
        self.params = params;
        gpu.queue
            .write_buffer(&self.params_buffer, 0, bytemuck::bytes_of(&self.params));
        if rebind {
            self.bind_group = make_bind_group(
                gpu,
                &self.layout,
                &self.params_buffer,
                &self.buffers,
                &self.layers,
            );
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.clear_buffer(&self.buffers[ACCUMULATION], 0, None);
        encoder.clear_buffer(&self.buffers[FOG_ACCUMULATION], 0, None);
        gpu.queue.submit([encoder.finish()]);
        self.frames = 0;
        self.uploaded = Uploaded {
            scene: scene_buffers,
            light_maps,
            faces,
            layers: self.uploaded.layers,
        };
        if all_maps {
            self.build_maps(gpu)?;
            update.maps = MapsRebuilt::All;
        } else if !moved_lights.is_empty() {
            self.rebuild_light_maps(gpu, &moved_lights)?;
            update.maps = MapsRebuilt::Lights(moved_lights);
            if self.uploaded.layers.mostly_unused() {
                self.build_maps(gpu)?;
                update.maps = MapsRebuilt::All;
            }
        }
        Ok(update)
    }

    /// Writes `items` into buffer `index` (binding `index + 1`), or into a
    /// new buffer when the size differs; says whether it is new.
    fn rewrite<T: Pod + Default>(
        &mut self,
        gpu: &Gpu,
        index: usize,
        label: &str,
        items: &[T],
    ) -> bool {
        let one = [T::default()];
        let items = if items.is_empty() { &one[..] } else { items };
        let bytes: &[u8] = bytemuck::cast_slice(items);
        if bytes.len() as u64 == self.buffers[index].size() {
            gpu.queue.write_buffer(&self.buffers[index], 0, bytes);
            false
        } else {
            self.buffers[index] = storage(gpu, label, items);
            true
        }
    }

    /// The march's bind group with `faces` in place of the face array
    /// (binding 5): the map kernels then trace only those faces, whose
    /// `texel_base` still places their texels in the whole map.
    fn bind_group_with_faces(&self, gpu: &Gpu, faces: &wgpu::Buffer) -> wgpu::BindGroup {
        let mut buffers: Vec<wgpu::Buffer> = self.buffers.clone();
        buffers[4] = faces.clone();
        make_bind_group(
            gpu,
            &self.layout,
            &self.params_buffer,
            &buffers,
            &self.layers,
        )
    }

    fn dispatch_with(
        &self,
        gpu: &Gpu,
        pipeline: &wgpu::ComputePipeline,
        bind_group: &wgpu::BindGroup,
        groups: (u32, u32, u32),
    ) {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_compute_pass(&Default::default());
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            pass.dispatch_workgroups(groups.0, groups.1, groups.2);
        }
        gpu.queue.submit([encoder.finish()]);
    }

    /// Renders the maps of `lights` again, keeping the other lights'
    /// (same face layout as before): their faces are traced again and take
    /// new spans after the layers handed out so far (the array grown,
    /// keeping those, if needed), then their layers are written. Their
    /// old layers stay in the array unused. Waits for the GPU.
    fn rebuild_light_maps(&mut self, gpu: &Gpu, lights: &[usize]) -> Result<(), GpuError> {
        let r = self.params.map_resolution;
        let groups = |faces: usize| (r.div_ceil(8), r.div_ceil(8), faces as u32);
        let face_buffers: Vec<(usize, wgpu::Buffer)> = lights
            .iter()
            .map(|&light| {
                let faces: &[GpuFace] =
                    &self.uploaded.faces[self.uploaded.light_maps[light].face_range()];
                (faces.len(), storage(gpu, "faces of a light", faces))
            })
            .collect();
        for (count, faces) in &face_buffers {
            let bind_group = self.bind_group_with_faces(gpu, faces);
            self.dispatch_with(gpu, &self.map_count_pipeline, &bind_group, groups(*count));
        }
        let taken = self.read_layers_taken(gpu)?;
        self.reserve_layers(gpu, taken, self.uploaded.layers.taken)?;
        for (count, faces) in &face_buffers {
            let bind_group = self.bind_group_with_faces(gpu, faces);
            self.dispatch_with(gpu, &self.map_layers_pipeline, &bind_group, groups(*count));
        }
        self.uploaded.layers.taken = taken;
        self.wait(gpu)
    }
}
