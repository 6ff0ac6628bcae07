// TODO: implemented by the RayTracer work item
