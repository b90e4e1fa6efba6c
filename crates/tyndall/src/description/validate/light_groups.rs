//! Validation of the light groups' memberships: each names an emitter of
//! the description, once, by a group name that is a layer name (ASCII
//! letters, digits, `_`, `-`) and not the reserved one, and the groups fit
//! the render's per-sample split.

use super::Item;
use crate::description::{DescError, GroupMember, LightGroupMember, SceneDesc};
use crate::light_groups::{MAX_LIGHT_GROUPS, MAX_NAME_BYTES, OTHER_NAME, is_group_name};

impl SceneDesc {
    /// Every membership of [`SceneDesc::light_groups`], in order.
    pub(super) fn validate_light_groups(&self) -> Result<(), DescError> {
        let mut names: Vec<&str> = Vec::new();
        for (k, membership) in self.light_groups.iter().enumerate() {
            let LightGroupMember {
                member,
                group,
                origin,
            } = membership;
            let item = Item { origin };
            if !is_group_name(group) {
                return item.fail(
                    "light_group",
                    format!(
                        "a light group's name is 1 to {MAX_NAME_BYTES} ASCII letters, digits, `_` and `-` (it names EXR layers, as Blender's light groups do), got {group:?}"
                    ),
                );
            }
            if group == OTHER_NAME {
                return item.fail(
                    "light_group",
                    format!(
                        "`{OTHER_NAME}` is the group of the light in no named group; name the group otherwise"
                    ),
                );
            }
            let emits = match *member {
                GroupMember::Light(i) => i < self.lights.len(),
                GroupMember::Shape(i) => self
                    .shapes
                    .get(i)
                    .is_some_and(|s| self.is_emissive(s.material)),
            };
            if !emits {
                return item.fail(
                    "light_group",
                    "only lights and emissive shapes can be in a light group".into(),
                );
            }
            if self.light_groups[..k].iter().any(|m| m.member == *member) {
                return item.fail(
                    "light_group",
                    "this emitter is already in a light group: it can be in one only".into(),
                );
            }
            if !names.contains(&group.as_str()) {
                names.push(group);
                if names.len() >= MAX_LIGHT_GROUPS {
                    return item.fail(
                        "light_group",
                        format!(
                            "a scene may name at most {} light groups (with `{OTHER_NAME}`, {MAX_LIGHT_GROUPS})",
                            MAX_LIGHT_GROUPS - 1
                        ),
                    );
                }
            }
        }
        Ok(())
    }
}
