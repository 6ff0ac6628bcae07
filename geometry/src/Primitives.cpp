// TODO: implemented by the Primitives work item
