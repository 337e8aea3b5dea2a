/* visfield from C: a scene from arrays (a unit square floor and a small square roof above it),
 * two structures, closest hits and occlusion for a batch of rays, and one error on purpose.
 * Build: cc visfield_example.c $(pkg-config --cflags --libs visfield) */
#include <stdio.h>
#include <visfield/visfield.h>

static int check(vf_error code) {
  if (code != VF_OK) fprintf(stderr, "visfield error %d: %s\n", (int)code, vf_last_error_message());
  return code == VF_OK;
}

int main(void) {
  const float vertices[] = {0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1,              /* floor, y = 0 */
                            0.25f, 1, 0.25f, 0.75f, 1, 0.25f, 0.75f, 1, 0.75f, 0.25f, 1, 0.75f}; /* roof, y = 1 */
  const uint32_t indices[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  const float lift[12] = {1, 0, 0, 0, 0, 1, 0, 0.5f, 0, 0, 1, 0}; /* the roof's copy, 0.5 higher */
  vf_scene scene = NULL;
  vf_structure bvh = NULL, beam = NULL;
  uint32_t mesh = 0, first = 0, second = 0;
  if (!check(vf_scene_create(&scene)) || !check(vf_scene_add_mesh(scene, vertices, 8, indices, 4, &mesh)) ||
      !check(vf_scene_add_instance(scene, mesh, NULL, &first)) || !check(vf_scene_add_instance(scene, mesh, lift, &second)))
    return 1;
  if (!check(vf_structure_build(scene, "bvh", &bvh)) || !check(vf_structure_build(scene, "beam:dirs=129,n=16", &beam))) return 1;

  /* Straight down from above: through the roof (inside the square) or onto the floor (outside it). */
  vf_ray rays[3] = {{0.5f, 3, 0.5f, 0, -1, 0, 0, 1e30f}, {0.1f, 3, 0.1f, 0, -1, 0, 0, 1e30f}, {0.5f, 3, 0.5f, 1, 0, 0, 0, 1e30f}};
  vf_hit hits[3], beam_hits[3];
  uint8_t blocked[3];
  if (!check(vf_intersect(bvh, rays, 3, hits)) || !check(vf_intersect(beam, rays, 3, beam_hits)) ||
      !check(vf_occluded(bvh, rays, 3, blocked)))
    return 1;
  for (int i = 0; i < 3; ++i) {
    if (hits[i].instance == VF_INVALID_ID)
      printf("ray %d: miss (occluded %d)\n", i, blocked[i]);
    else
      printf("ray %d: t %.3f, object %u, triangle %u (occluded %d; BeamField t %.3f)\n", i, hits[i].t, hits[i].instance,
             hits[i].prim, blocked[i], beam_hits[i].t);
  }

  /* BeamField moves objects without a rebuild; a BVH says it cannot. */
  const float away[12] = {1, 0, 0, 5, 0, 1, 0, 0.5f, 0, 0, 1, 0};
  if (!check(vf_structure_move(beam, second, away)) || !check(vf_structure_commit(beam))) return 1;
  if (!check(vf_intersect(beam, rays, 1, beam_hits))) return 1;
  printf("after the move: t %.3f (object %u)\n", beam_hits[0].t, beam_hits[0].instance);
  vf_error refused = vf_structure_move(bvh, second, away);
  printf("bvh move: error %d: %s\n", (int)refused, vf_last_error_message());

  vf_structure_release(beam);
  vf_structure_release(bvh);
  vf_scene_release(scene);
  return refused == VF_ERROR_UNSUPPORTED && hits[0].instance == second && hits[1].instance == second && beam_hits[0].instance == first ? 0 : 1;
}
