// TODO: implemented by the Analytic work item
