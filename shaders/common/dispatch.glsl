// The index of this invocation in a gl::dispatch_linear dispatch (native/src/gl/objects.h): its work groups fill
// rows of at most 65,535, so large counts need the row as well as gl_GlobalInvocationID.x. Included after the
// shader declares its local size (gl_WorkGroupSize needs it).
uint linear_invocation() {
  return (gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x) * gl_WorkGroupSize.x + gl_LocalInvocationID.x;
}
