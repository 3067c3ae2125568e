//! The reader takes a file's items one at a time (the `document` module), so a scene of many
//! items is read without holding a tree of them all. Measured by counting the bytes the
//! allocator hands out: a test binary of its own, so no other test's allocations count.
use rayforge_scene::load_str;
use std::path::Path;

mod counting;
use counting::peak_of;

mod common;
use common::many_items;

#[test]
fn a_scene_of_many_items_is_read_without_holding_a_tree_of_them_all() {
    let n = 20_000;
    let text = many_items(n);
    let (scene, peak, kept) =
        peak_of(|| load_str(&text, Path::new("many.yml")).expect("the scene loads"));
    assert_eq!(scene.world.objects.len(), n);
    // What the scene keeps is about 0.7-0.8 KB an object; saphyr's tree of the whole file would
    // add about 5 KB an item on top while the world is built (over 100 MB here). Allowed: the
    // object list's last doubling (old and new lists held at once) and a few MB of reader
    // state.
    let allowed = 2 * kept + (4 << 20);
    assert!(
        peak <= allowed,
        "reading held {} MB at its peak for a scene that keeps {} MB (allowed {} MB)",
        peak >> 20,
        kept >> 20,
        allowed >> 20
    );
}
